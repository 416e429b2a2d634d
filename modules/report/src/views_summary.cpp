#include "photoscene/report/views_summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "photoscene/core/error.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/io/scene_json.hpp"
#include "photoscene/report/report.hpp"

namespace ps::report {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

double number(const json& j, const char* key, double fallback) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : fallback;
}

/// ", masks 0.97" where the view's mask consistency was recorded
std::string maskText(const ViewsSummary::Seen& v) {
  return v.maskConsistency >= 0 ? fmt::format(", masks {:.2f}", v.maskConsistency) : "";
}

}  // namespace

ViewsSummary summarizeViews(const fs::path& outDir) {
  ViewsSummary s;
  const io::SceneDesc desc = io::readSceneJson(outDir / "scene.json");
  std::vector<double> exposure;
  if (fs::exists(outDir / "lights.json"))
    exposure = io::readLightsJson(outDir / "lights.json").exposure;
  for (size_t i = 0; i < desc.views.size(); ++i) {
    ViewsSummary::View v;
    v.index = static_cast<int>(i);
    const fs::path r = desc.views[i].image.lexically_relative(desc.baseDir);
    v.image = r.empty() ? desc.views[i].image.string() : r.generic_string();
    v.exposure = i < exposure.size() ? exposure[i] : 1.0;
    s.views.push_back(v);
  }
  const fs::path materials = outDir / "materials";
  if (fs::is_directory(materials)) {
    for (const auto& e : fs::directory_iterator(materials)) {
      if (e.path().extension() != ".json") continue;
      const json m = io::readJsonFile(e.path());
      ViewsSummary::Part p;
      p.part = m.value("part", e.path().stem().string());
      const json fit = m.value("fit", json::object());
      if (fit.contains("view") && fit["view"].is_number_integer()) p.view = fit["view"].get<int>();
      if (fit.contains("views") && fit["views"].is_array())
        for (const json& v : fit["views"]) {
          if (!v.is_object()) continue;
          ViewsSummary::Seen seen;
          seen.view = static_cast<int>(number(v, "view", -1));
          seen.pixels = static_cast<int>(number(v, "pixels", 0));
          seen.meanCosine = number(v, "mean_cosine", 0);
          seen.agreement = number(v, "agreement", 1);
          seen.score = number(v, "score", 0);
          seen.maskConsistency = number(v, "mask_consistency", -1);
          p.seen.push_back(seen);
        }
      if (p.view >= 0 && p.view < static_cast<int>(s.views.size())) ++s.views[p.view].parts;
      s.parts.push_back(std::move(p));
    }
    std::sort(
        s.parts.begin(), s.parts.end(),
        [](const ViewsSummary::Part& a, const ViewsSummary::Part& b) { return a.part < b.part; });
  }
  if (fs::exists(outDir / "poses.json")) {
    const json j = io::readJsonFile(outDir / "poses.json");
    for (const json& o : j.value("objects", json::array())) {
      if (!o.is_object()) continue;
      ViewsSummary::Object b;
      b.name = o.value("object", std::string("?"));
      b.moved = o.value("moved", false);
      const json shift = o.value("shift", json::array());
      double sq = 0;
      for (const json& c : shift) sq += c.is_number() ? c.get<double>() * c.get<double>() : 0;
      b.shiftCm = 100 * std::sqrt(sq);
      b.yawDeg = number(o, "yaw_deg", 0);
      b.scale = number(o, "scale", 1);
      b.pixels = static_cast<int>(number(o, "labelled_pixels", 0));
      b.before = static_cast<int>(number(o, "mislabelled_before", 0));
      b.after = static_cast<int>(number(o, "mislabelled_after", 0));
      s.objects.push_back(b);
    }
  }
  return s;
}

namespace {
std::string moveText(const ViewsSummary::Object& o) {
  return o.moved ? fmt::format("moved {:.1f} cm, turned {:.2f} deg, scaled {:.3f}", o.shiftCm,
                               o.yawDeg, o.scale)
                 : std::string("kept");
}
}  // namespace

std::string viewsText(const ViewsSummary& s) {
  std::ostringstream o;
  for (const auto& v : s.views)
    o << fmt::format("view {}     exposure {:.4f}, {} parts fitted in it, {}\n", v.index,
                     v.exposure, v.parts, v.image);
  for (const auto& p : s.parts) {
    if (p.view < 0) continue;
    o << fmt::format("  part {:<28} view {}", p.part, p.view);
    if (!p.seen.empty()) {
      o << "   (score = pixels x cos x agreement:";
      for (const auto& v : p.seen)
        o << fmt::format(" view {}{} {:.0f} = {} x {:.2f} x {:.2f}", v.view,
                         v.view == p.view ? "*" : "", v.score, v.pixels, v.meanCosine, v.agreement)
          << maskText(v) << (&v == &p.seen.back() ? ")" : ";");
    }
    o << "\n";
  }
  for (const auto& b : s.objects)
    o << fmt::format("object {:<26} {} (labelled pixels mislabelled {} -> {}, {} its own)\n",
                     b.name, moveText(b), b.before, b.after, b.pixels);
  return o.str();
}

std::string viewsHtml(const ViewsSummary& s) {
  std::ostringstream h;
  h << "<section id=\"view-choice\"><h2>Views, exposures and the view each part was fitted "
       "in</h2>\n<table><thead><tr><th>view</th><th>photo</th><th>exposure</th><th>parts fitted "
       "in it</th></tr></thead><tbody>\n";
  for (const auto& v : s.views)
    h << "<tr><td>" << v.index << "</td><td>" << escapeHtml(v.image) << "</td><td>"
      << fmt::format("{:.4f}", v.exposure) << "</td><td>" << v.parts << "</td></tr>\n";
  h << "</tbody></table>\n";
  const bool scored = std::any_of(s.parts.begin(), s.parts.end(),
                                  [](const ViewsSummary::Part& p) { return !p.seen.empty(); });
  if (scored) {
    h << "<p class=\"note\">Per part, every view that sees it: score = M_aln pixels &times; mean "
         "|cos| to the camera &times; appearance agreement with the other views (after their "
         "exposures); the highest score is the view it was fitted in (bold). \"masks\": of the "
         "points of the part's aligned masks in the other views that this view sees on the part, "
         "the share in its aligned mask (a low share: its photo region misses the part).</p>\n"
         "<table><thead><tr><th>part</th><th>view</th><th>scores (view: pixels &times; cos "
         "&times; agreement = score)</th></tr></thead><tbody>\n";
    for (const auto& p : s.parts) {
      if (p.view < 0) continue;
      h << "<tr><td>" << escapeHtml(p.part) << "</td><td>" << p.view << "</td><td>";
      for (const auto& v : p.seen) {
        const std::string cell = fmt::format("{}: {} &times; {:.2f} &times; {:.2f} = {:.0f}",
                                             v.view, v.pixels, v.meanCosine, v.agreement, v.score) +
                                 maskText(v);
        h << (v.view == p.view ? "<b>" + cell + "</b>" : cell)
          << (&v == &p.seen.back() ? "" : "; ");
      }
      h << "</td></tr>\n";
    }
    h << "</tbody></table>\n";
  }
  if (!s.objects.empty()) {
    h << "<p class=\"note\">The objects of the CAD model moved onto the parts the views' labels "
         "give them (stage poses; scene.json options.refine_poses: false keeps the geometry): "
         "labelled pixels whose part the render gets wrong around each object, before and "
         "after.</p>\n<table><thead><tr><th>object</th><th>pose</th><th>mislabelled "
         "pixels</th><th>its own labelled pixels</th></tr></thead><tbody>\n";
    for (const auto& b : s.objects)
      h << "<tr><td>" << escapeHtml(b.name) << "</td><td>" << moveText(b) << "</td><td>" << b.before
        << " &rarr; " << b.after << "</td><td>" << b.pixels << "</td></tr>\n";
    h << "</tbody></table>\n";
  }
  h << "</section>\n";
  return h.str();
}

}  // namespace ps::report

// Rendering the report (report_data.hpp): the page of a ReportData, section by section, reading
// no file. The style sheet and the page script are constants below; each section is one function
// writing HTML to a stream.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "photoscene/core/image.hpp"
#include "report_data.hpp"

namespace ps {

/// & < > " ' as HTML entities (text and attribute values).
std::string escapeHtml(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      case '\'':
        o += "&#39;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

namespace report_detail {

namespace {

std::string html(const std::string& s) {
  return escapeHtml(s);
}

std::string fmtNum(double v, int digits = 4) {
  if (!std::isfinite(v)) return "&ndash;";
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

std::string paramText(const json& v) {
  if (v.is_number()) return fmtNum(v.get<double>(), 3);
  if (v.is_array()) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + paramText(v[i]);
    return s + "]";
  }
  if (v.is_string()) return html(v.get<std::string>());
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  return html(v.dump());
}

/// Inline SVG polyline of a loss curve.
std::string lossCurveSvg(const json& history) {
  std::vector<double> v;
  for (const auto& x : history)
    if (x.is_number() && std::isfinite(x.get<double>())) v.push_back(x.get<double>());
  if (v.size() < 2) return "";
  const double lo = *std::min_element(v.begin(), v.end()),
               hi = *std::max_element(v.begin(), v.end());
  const bool logScale = lo > 0 && hi / lo > 20;
  auto y = [&](double x) {
    const double a = logScale ? std::log(x) : x, l = logScale ? std::log(lo) : lo,
                 h = logScale ? std::log(hi) : hi;
    return h > l ? 38.0 - 36.0 * (a - l) / (h - l) : 20.0;
  };
  std::ostringstream os;
  os << "<svg class=\"curve\" viewBox=\"0 0 160 40\" width=\"160\" height=\"40\"><polyline "
        "fill=\"none\" "
        "stroke=\"#2a7fd4\" stroke-width=\"1.5\" points=\"";
  for (size_t i = 0; i < v.size(); ++i)
    os << (i ? " " : "") << fmtNum(2.0 + 156.0 * i / (v.size() - 1), 5) << ","
       << fmtNum(y(v[i]), 5);
  os << "\"/><title>loss " << fmtNum(v.front()) << " &rarr; " << fmtNum(v.back()) << " over "
     << v.size() << " steps" << (logScale ? " (log scale)" : "") << "</title></svg>";
  return os.str();
}

std::string metricCells(const json* m, const std::vector<std::string>& keys) {
  std::string s;
  for (const auto& k : keys) s += "<td>" + fmtNum(m ? num(at(*m, k)) : std::nan("")) + "</td>";
  return s;
}

const char* kStyle = R"CSS(
body{font:14px/1.45 system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:0;background:#f6f7f9;color:#1d2330}
header{background:#1d2330;color:#fff;padding:14px 24px}header h1{margin:0;font-size:20px}
header .sub{opacity:.75;font-size:13px}main{padding:16px 24px;max-width:1400px}
section{background:#fff;border-radius:8px;box-shadow:0 1px 3px rgba(0,0,0,.08);padding:14px 18px;margin:0 0 18px}
h2{font-size:16px;margin:0 0 10px}table{border-collapse:collapse;font-size:13px}
th,td{border-bottom:1px solid #e3e6ea;padding:4px 8px;text-align:left;vertical-align:top}
th{background:#f0f2f5;font-weight:600}td.num{text-align:right}
#viewer{position:relative;width:100%;height:520px;background:#1e2226;border-radius:6px;overflow:hidden}
#viewer canvas{display:block;width:100%;height:100%}
.ps-status{position:absolute;left:12px;top:10px;color:#ddd;font-size:13px}.ps-error{color:#ff8a80}
.buttons{margin:8px 0 0}.buttons button{margin:0 6px 6px 0;padding:4px 10px;border:1px solid #bbc;border-radius:4px;background:#fff;cursor:pointer}
.buttons button:hover{background:#eef}
.views{display:flex;flex-wrap:wrap;gap:18px}.view{flex:0 1 auto}
.wipe{position:relative;display:inline-block;line-height:0}.wipe img{max-width:640px;width:100%}
.wipe .over{position:absolute;left:0;top:0;clip-path:inset(0 0 0 50%)}
.wipe .bar{position:absolute;top:0;bottom:0;left:50%;width:2px;background:#fff;box-shadow:0 0 3px #000;pointer-events:none}
.wipe input{display:block;width:100%;margin:6px 0 0}
.trio{display:flex;gap:6px;margin-top:6px}.trio figure{margin:0;font-size:12px;text-align:center}
.trio img{width:200px;display:block}.missing{color:#999;font-style:italic}
td.maps{white-space:nowrap}img.thumb,span.thumb{width:56px;height:56px;object-fit:cover;border:1px solid #ccd;image-rendering:auto}
.params{font-size:12px;color:#445}.bar{display:inline-block;height:10px;background:#2a7fd4;border-radius:2px}
.note{color:#666;font-size:12px}
.cands{white-space:nowrap}.cand{display:inline-block;margin:0 8px 4px 0;text-align:center;font-size:12px;vertical-align:top}
.cand img.thumb{width:72px;height:72px}.cand.chosen img.thumb{outline:2px solid #2a7fd4}
)CSS";

const char* kPageScript = R"JS(
document.querySelectorAll('.wipe').forEach(function (w) {
  var input = w.querySelector('input'), over = w.querySelector('.over'), bar = w.querySelector('.bar');
  if (!input || !over) return;
  var update = function () {
    over.style.clipPath = 'inset(0 0 0 ' + input.value + '%)';
    if (bar) bar.style.left = input.value + '%';
  };
  input.addEventListener('input', update);
  update();
});
(function () {
  var box = document.getElementById('viewer');
  if (!box) return;
  if (!window.PhotosceneViewer) {
    box.innerHTML = '<div class="ps-status ps-error">The 3D viewer script (viewer/photoscene-viewer.js) is missing.</div>';
    return;
  }
  var cfg = JSON.parse(document.getElementById('ps-viewer-config').textContent);
  var v = window.PhotosceneViewer.start(box, cfg);
  document.querySelectorAll('button[data-view]').forEach(function (b) {
    b.addEventListener('click', function () {
      var i = parseInt(b.getAttribute('data-view'), 10);
      if (i < 0) { if (v) v.overview(); } else if (v) { v.goToView(i); }
    });
  });
})();
)JS";

void renderHeader(std::ostream& h, const ReportData& d) {
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
    << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
    << "<link rel=\"icon\" href=\"data:,\">\n"
    << "<title>" << html(d.title) << "</title>\n<style>" << kStyle << "</style></head><body>\n";
  h << "<header><h1>" << html(d.title) << "</h1><div class=\"sub\">" << d.views.size()
    << " view(s), " << d.parts.size() << " parts";
  if (!d.preset.empty()) h << ", preset " << html(d.preset);
  if (std::isfinite(d.totalSeconds)) h << ", " << fmtNum(d.totalSeconds, 4) << " s in total";
  h << "</div></header>\n<main>\n";
}

void renderViewer(std::ostream& h, const ReportData& d) {
  h << "<section id=\"viewer-section\"><h2>Digital twin (twin.gltf)</h2>\n";
  if (d.viewerWritten) {
    json cfg = {{"views", json::array()}, {"emitters", d.emitters}};
    for (const auto& v : d.views) {
      json rows = json::array();
      for (int r = 0; r < 4; ++r)
        rows.push_back({v.camera.worldToCamera(r, 0), v.camera.worldToCamera(r, 1),
                        v.camera.worldToCamera(r, 2), v.camera.worldToCamera(r, 3)});
      cfg["views"].push_back({{"name", "view" + std::to_string(v.index)},
                              {"width", v.camera.width},
                              {"height", v.camera.height},
                              {"fx", v.camera.fx},
                              {"fy", v.camera.fy},
                              {"cx", v.camera.cx},
                              {"cy", v.camera.cy},
                              {"world_to_camera", rows}});
    }
    std::string cfgText = cfg.dump();
    // keep "</script>" out of the inline JSON
    for (size_t p = 0; (p = cfgText.find("</", p)) != std::string::npos; p += 3)
      cfgText.replace(p, 2, "<\\/");
    h << "<div id=\"viewer\"></div>\n<div class=\"buttons\"><button "
         "data-view=\"-1\">Overview</button>";
    for (const auto& v : d.views)
      h << "<button data-view=\"" << v.index << "\">Go to input view " << v.index << "</button>";
    h << "</div>\n<div class=\"note\">Drag to orbit, scroll to zoom, right-drag to pan. Lighting "
         "in the viewer is "
         "approximate (hemisphere light plus the emitters); the renders below are the path-traced "
         "twin.</div>\n"
      << "<script type=\"application/json\" id=\"ps-viewer-config\">" << cfgText << "</script>\n";
  } else {
    h << "<p class=\"missing\">" << html(d.viewerNote) << "</p>\n";
  }
  h << "</section>\n";
}

void renderViews(std::ostream& h, const ReportData& d) {
  h << "<section id=\"views\"><h2>Input views: photo, render, difference</h2><div "
       "class=\"views\">\n";
  for (const auto& v : d.views) {
    h << "<div class=\"view\" id=\"view" << v.index << "\"><h3>View " << v.index << "</h3>\n";
    if (!v.photoUrl.empty() && !v.renderUrl.empty()) {
      h << "<div class=\"wipe\"><img src=\"" << html(v.photoUrl) << "\" alt=\"photo " << v.index
        << "\"><img class=\"over\" src=\"" << html(v.renderUrl) << "\" alt=\"render " << v.index
        << "\"><div class=\"bar\"></div><input type=\"range\" min=\"0\" max=\"100\" value=\"50\" "
           "aria-label=\"wipe between photo (left) and render (right)\"></div>\n"
        << "<div class=\"note\">Slide: photo on the left, render on the right.</div>\n";
    }
    h << "<div class=\"trio\">";
    auto fig = [&](const std::string& url, const std::string& what, const std::string& missing) {
      h << "<figure>";
      if (url.empty())
        h << "<div class=\"missing\">" << html(missing) << "</div>";
      else
        h << "<a href=\"" << html(url) << "\"><img src=\"" << html(url) << "\" alt=\"" << what
          << "\"></a>";
      h << "<figcaption>" << what << "</figcaption></figure>";
    };
    fig(v.photoUrl, "photo", "photo missing");
    fig(v.renderUrl, "render", "no renders/view" + std::to_string(v.index) + ".png");
    fig(v.diffUrl, "|render &minus; photo| &times; 4", "no difference image");
    h << "</div>";
    if (!v.note.empty()) h << "<div class=\"missing\">" << html(v.note) << "</div>";
    if (v.metrics.is_object()) {
      const json* s = at(v.metrics, "srgb255");
      h << "<div class=\"note\">PSNR " << fmtNum(s ? num(at(*s, "psnr")) : std::nan(""))
        << " dB, SSIM " << fmtNum(s ? num(at(*s, "ssim")) : std::nan("")) << ", RMSE (sRGB 0-255) "
        << fmtNum(s ? num(at(*s, "rmse")) : std::nan("")) << "</div>";
    }
    h << "</div>\n";
  }
  if (d.views.empty()) h << "<p class=\"missing\">scene.json has no views.</p>";
  h << "</div></section>\n";
}

// The maps cell: thumbnails of the maps, or a swatch of a homogeneous albedo.
void renderMaps(std::ostream& h, const ReportPart& p) {
  for (const auto& [k, url] : p.mapUrls)
    h << "<a href=\"" << html(url) << "\"><img class=\"thumb\" src=\"" << html(url) << "\" alt=\""
      << k << "\" title=\"" << k << "\"></a> ";
  if (!p.mapUrls.empty() || (at(p.material, "maps") && at(p.material, "maps")->is_object())) return;
  if (const json* hom = at(p.material, "homogeneous")) {
    if (const json* a = at(*hom, "albedo"); a && a->is_array() && a->size() == 3) {
      auto c = [&](int i) {
        const double lin = (*a)[i].is_number() ? (*a)[i].get<double>() : 0.5;
        return static_cast<int>(
            std::lround(255.0 * std::clamp(linearToSrgb(static_cast<float>(lin)), 0.0f, 1.0f)));
      };
      h << "<span class=\"thumb\" style=\"display:inline-block;background:rgb(" << c(0) << ","
        << c(1) << "," << c(2) << ")\" title=\"homogeneous albedo\"></span>";
    }
  }
}

void renderPartRow(std::ostream& h, const ReportPart& p, const ReportOptions& options) {
  const json& m = p.material;
  auto str = [&](const char* k) {
    const json* v = at(m, k);
    return v && v->is_string() ? html(v->get<std::string>()) : std::string();
  };
  h << "<tr id=\"part-" << html(p.name) << "\"><td><b>" << html(p.name) << "</b>";
  if (!p.role.empty()) h << "<br><span class=\"note\">" << p.role << "</span>";
  h << "</td><td>" << str("graph") << "</td><td>" << str("category") << "</td><td class=\"maps\">";
  renderMaps(h, p);
  h << "</td><td class=\"params\">";
  if (const json* pr = at(m, "params"); pr && pr->is_object()) {
    int n = 0;
    for (auto it = pr->begin(); it != pr->end() && n < options.maxParamsPerPart; ++it, ++n)
      h << html(it.key()) << " = " << paramText(it.value()) << "<br>";
    if (static_cast<int>(pr->size()) > options.maxParamsPerPart)
      h << "&hellip; " << (pr->size() - options.maxParamsPerPart) << " more";
  }
  if (const json* hom = at(m, "homogeneous"); hom && !at(m, "maps")) {
    if (const json* r = at(*hom, "roughness")) h << "roughness = " << paramText(*r) << "<br>";
  }
  h << "</td><td class=\"params\">";
  if (const json* uv = at(m, "uv_transform")) {
    if (const json* r = at(*uv, "rotation_deg")) h << "rot " << paramText(*r) << "&deg;<br>";
    if (const json* s = at(*uv, "scale")) h << "scale " << paramText(*s) << "<br>";
    if (const json* o = at(*uv, "offset")) h << "offset " << paramText(*o);
  }
  const json* fit = at(m, "fit");
  const json empty = json::object();
  const json& f = fit ? *fit : empty;
  h << "</td><td class=\"num\">" << (at(f, "view") ? paramText(*at(f, "view")) : "&ndash;")
    << "</td><td class=\"num\">" << fmtNum(num(at(f, "loss"))) << "</td><td>"
    << (at(f, "history") ? lossCurveSvg(*at(f, "history")) : "") << "</td><td class=\"num\">"
    << fmtNum(num(at(f, "seconds")), 3) << "</td><td class=\"num\">"
    << fmtNum(num(path(p.metrics, {"srgb255", "rmse"}))) << "</td><td>";
  if (const json* s = at(f, "skipped"); s && s->is_string()) h << html(s->get<std::string>());
  if (!p.note.empty()) h << "<span class=\"missing\">" << html(p.note) << "</span>";
  h << "</td></tr>\n";
}

void renderParts(std::ostream& h, const ReportData& d, const ReportOptions& options) {
  h << "<section id=\"parts\"><h2>Materials per part</h2>\n";
  if (!d.partsNote.empty()) h << "<p class=\"note\">" << html(d.partsNote) << "</p>";
  h << "<table><thead><tr><th>part</th><th>graph</th><th>category</th><th>maps</th><th>key "
       "parameters</th>"
       "<th>UV transform</th><th>fit view</th><th>loss</th><th>loss "
       "curve</th><th>seconds</th><th>RMSE (sRGB)</th>"
       "<th>skipped</th></tr></thead><tbody>\n";
  for (const ReportPart& p : d.parts) renderPartRow(h, p, options);
  h << "</tbody></table></section>\n";
}

// Per part the graphs the selection ranked (top 5, score = the kNN vote's weight), with a
// preview of each at its default parameters, and how to force one.
void renderCandidates(std::ostream& h, const ReportData& d) {
  bool any = false;
  for (const ReportPart& p : d.parts) any = any || !p.candidates.empty();
  if (!any) return;
  h << "<section id=\"candidates\"><h2>Graph choice per part</h2>\n<p class=\"note\">The "
       "selection's top candidates (kNN vote over the exemplar bank: score is the summed weight "
       "of the votes; the chosen graph is marked). Previews show each graph at its default "
       "parameters. To force a graph, set it in scene.json and rerun (only that part and what "
       "reads every part is redone): <code>\"parts\": { \"&lt;part&gt;\": { \"graph\": "
       "\"&lt;graph&gt;\" } }</code>, or give its material category and let selection choose "
       "among that category's graphs: <code>\"parts\": { \"&lt;part&gt;\": { \"category\": "
       "\"wood\" } }</code>.</p>\n<table><thead><tr><th>part</th><th>candidates (best "
       "first)</th><th>force with</th></tr></thead><tbody>\n";
  for (const ReportPart& p : d.parts) {
    if (p.candidates.empty()) continue;
    h << "<tr id=\"candidates-" << html(p.name) << "\"><td><b>" << html(p.name)
      << "</b></td><td class=\"cands\">";
    for (const ReportCandidate& c : p.candidates) {
      h << "<figure class=\"cand" << (c.chosen ? " chosen" : "") << "\">";
      if (c.previewUrl.empty())
        h << "<span class=\"thumb missing\">no preview</span>";
      else
        h << "<img class=\"thumb\" src=\"" << html(c.previewUrl) << "\" alt=\"" << html(c.graph)
          << "\">";
      h << "<figcaption>" << (c.chosen ? "<b>" : "") << html(c.graph) << (c.chosen ? "</b>" : "")
        << "<br><span class=\"note\">" << html(c.category) << ", score " << fmtNum(c.score, 3)
        << ", " << c.votes << " vote" << (c.votes == 1 ? "" : "s") << "</span></figcaption>"
        << "</figure>";
    }
    // why: the short fits on the part, and the tests a texture had to pass
    if (!p.finalists.empty()) {
      const std::string cells =
          std::to_string(p.coarseScale) + " x " + std::to_string(p.coarseScale) + " cells";
      h << "<p class=\"note finalists\">Decided by short fits on the part (lowest loss first): ";
      for (size_t i = 0; i < p.finalists.size(); ++i) {
        const ReportFinalist& f = p.finalists[i];
        h << (i ? "; " : "") << (f.chosen ? "<b>" : "") << html(f.graph) << (f.chosen ? "</b>" : "")
          << " loss " << fmtNum(f.loss, 3);
        if (std::isfinite(f.contrast) && f.graph != "homogeneous") {
          h << ", contrast " << fmtNum(f.contrast, 3);
          if (std::isfinite(f.coarseContrast) && f.coarseContrast > 0)
            h << " (" << fmtNum(f.coarseContrast, 3) << " at " << cells << ")";
          if (std::isfinite(f.chroma)) h << ", colour spread " << fmtNum(f.chroma, 3);
          if (std::isfinite(f.chromaOutside) && f.chromaOutside > 0)
            h << ", " << std::lround(100 * f.chromaOutside) << " % in colours the photo lacks";
        }
        if (!f.qualifies) h << " (more structure, colours or pixel error than the photo allows)";
      }
      h << ".";
      if (std::isfinite(p.photoContrast) && p.photoContrast > 0)
        h << " The photo's typical local contrast: " << fmtNum(p.photoContrast, 3)
          << (std::isfinite(p.photoCoarseContrast) && p.photoCoarseContrast > 0
                  ? " (" + fmtNum(p.photoCoarseContrast, 3) + " at " + cells + ")"
                  : std::string())
          << ".";
      if (std::isfinite(p.photoChroma) && p.photoChroma > 0)
        h << " Its colour spread: " << fmtNum(p.photoChroma, 3) << ".";
      if (p.categoryGiven.empty())
        h << " A graph must beat the homogeneous loss by the margin and pass the tests.";
      else
        h << " The scene gives the category <b>" << html(p.categoryGiven)
          << "</b>: only its graphs were finalists; one must beat the homogeneous loss by the"
             " margin and pass the tests (unless the selection options insist on a texture).";
      if (std::isfinite(p.photoCoarseContrast) && p.photoCoarseContrast > 0)
        h << " At " << cells << " a graph is judged by the contrast it adds to the homogeneous"
             " render's (the incident-light grid's noise is in both).";
      if (!p.textureRejected.empty())
        h << " The full fit of <b>" << html(p.textureRejected)
          << "</b> failed them: the part is homogeneous.";
      h << "</p>";
    }
    // the example forces the best candidate that was not chosen
    const ReportCandidate& example = *std::find_if(
        p.candidates.begin(), p.candidates.end() - 1, [](const auto& c) { return !c.chosen; });
    h << "</td><td><code>\"parts\": { \"" << html(p.name) << "\": { \"graph\": \""
      << html(example.graph) << "\" } }</code></td></tr>\n";
  }
  h << "</tbody></table></section>\n";
}

void renderMetrics(std::ostream& h, const ReportData& d) {
  const json& metrics = d.metrics;
  h << "<section id=\"metrics\"><h2>Metrics</h2>\n";
  if (!d.metricsNote.empty()) h << "<p class=\"missing\">" << html(d.metricsNote) << "</p>\n";
  const std::vector<std::string> keys = {"psnr", "ssim", "rmse", "gmsd"};
  auto imageTable = [&](const char* key, const char* label, const char* nameKey) {
    const json* arr = at(metrics, key);
    if (!arr || !arr->is_array() || arr->empty()) return;
    h << "<h3>" << label
      << "</h3><table><thead><tr><th></th><th>PSNR (sRGB)</th><th>SSIM (sRGB)</th>"
         "<th>RMSE (sRGB 0-255)</th><th>GMSD (sRGB)</th><th>PSNR (linear)</th><th>SSIM "
         "(linear)</th>"
         "<th>RMSE (linear)</th><th>GMSD (linear)</th></tr></thead><tbody>";
    for (const auto& e : *arr) {
      if (!e.is_object()) continue;
      std::string name;
      if (const json* n = at(e, nameKey)) name = n->is_string() ? n->get<std::string>() : n->dump();
      h << "<tr><td>" << html(name) << "</td>" << metricCells(at(e, "srgb255"), keys)
        << metricCells(at(e, "linear"), keys) << "</tr>";
    }
    h << "</tbody></table>\n";
  };
  imageTable("views", "Input views", "view");
  imageTable("novel", "Novel views", "name");
  imageTable("relit", "Relit views", "name");
  if (const json* st = at(metrics, "stages"); st && st->is_object() && !st->empty()) {
    double maxT = 0;
    for (const auto& [k, v] : st->items())
      if (v.is_number()) maxT = std::max(maxT, v.get<double>());
    h << "<h3>Time per stage</h3><table><tbody>";
    for (const auto& [k, v] : st->items()) {
      const double t = v.is_number() ? v.get<double>() : std::nan("");
      const double w = maxT > 0 && std::isfinite(t) ? 240.0 * t / maxT : 0;
      h << "<tr><td>" << html(k) << "</td><td class=\"num\">" << fmtNum(t, 3)
        << " s</td><td><span class=\"bar\" "
        << "style=\"width:" << fmtNum(std::max(w, 1.0), 4) << "px\"></span></td></tr>";
    }
    h << "</tbody></table>\n";
  }
  h << "</section>\n";
}

}  // namespace

std::string renderReportHtml(const ReportData& d, const ReportOptions& options) {
  std::ostringstream h;
  renderHeader(h, d);
  renderViewer(h, d);
  renderViews(h, d);
  // views, their exposures and each part's view (views_summary.cpp)
  h << d.viewChoiceHtml;
  if (!d.viewChoiceNote.empty()) h << "<p class=\"missing\">" << html(d.viewChoiceNote) << "</p>\n";
  renderParts(h, d, options);
  renderCandidates(h, d);
  renderMetrics(h, d);
  h << "</main>\n";
  if (d.viewerWritten)
    h << "<script src=\"viewer/twin_data.js\"></script>\n<script "
         "src=\"viewer/photoscene-viewer.js\"></script>\n";
  h << "<script>" << kPageScript << "</script>\n</body></html>\n";
  return h.str();
}

}  // namespace report_detail

}  // namespace ps

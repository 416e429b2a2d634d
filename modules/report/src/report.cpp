#include "photoscene/report/report.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "photoscene/core/data_folder.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/io/obj_io.hpp"
#include "photoscene/io/scene_json.hpp"
#include "photoscene/scene/gltf_export.hpp"
#include "photoscene/scene/material.hpp"
#include "photoscene/scene/scene.hpp"

namespace ps {

namespace fs = std::filesystem;
using nlohmann::json;

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

namespace {

// ---------------------------------------------------------------- small helpers

std::string html(const std::string& s) { return escapeHtml(s); }

/// A relative URL (from outDir) of a file, '/'-separated and percent-encoded.
std::string urlFor(const fs::path& file, const fs::path& outDir) {
  std::error_code ec;
  fs::path rel = fs::relative(fs::absolute(file), fs::absolute(outDir), ec);
  if (ec || rel.empty()) rel = fs::absolute(file);
  std::string o;
  for (unsigned char c : rel.generic_string()) {
    if (std::isalnum(c) ||
        std::string("-._~/!$&'()*+,;=:@").find(static_cast<char>(c)) != std::string::npos) {
      o += static_cast<char>(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof(buf), "%%%02X", c);
      o += buf;
    }
  }
  return o;
}

std::string fmtNum(double v, int digits = 4) {
  if (!std::isfinite(v)) return "&ndash;";
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

/// A number of a JSON value, or NaN.
double num(const json* j) {
  return j && j->is_number() ? j->get<double>() : std::nan("");
}
const json* at(const json& j, const std::string& key) {
  if (!j.is_object()) return nullptr;
  auto it = j.find(key);
  return it == j.end() || it->is_null() ? nullptr : &*it;
}
const json* path(const json& j, std::initializer_list<const char*> keys) {
  const json* cur = &j;
  for (const char* k : keys) {
    cur = at(*cur, k);
    if (!cur) return nullptr;
  }
  return cur;
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

std::string base64(const std::string& data) {
  static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  size_t i = 0;
  const auto* p = reinterpret_cast<const unsigned char*>(data.data());
  for (; i + 2 < data.size(); i += 3) {
    const uint32_t v = (p[i] << 16) | (p[i + 1] << 8) | p[i + 2];
    out += tbl[v >> 18];
    out += tbl[(v >> 12) & 63];
    out += tbl[(v >> 6) & 63];
    out += tbl[v & 63];
  }
  if (i < data.size()) {
    uint32_t v = p[i] << 16;
    if (i + 1 < data.size()) v |= p[i + 1] << 8;
    out += tbl[v >> 18];
    out += tbl[(v >> 12) & 63];
    out += i + 1 < data.size() ? tbl[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return {};
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// An image as embedded in the viewer data: the file's bytes, or (when larger than maxSize)
/// a downscaled PNG of it.
std::string imageDataUri(const fs::path& file, int maxSize) {
  const std::string ext = file.extension().string();
  const std::string mime = (ext == ".jpg" || ext == ".jpeg") ? "image/jpeg" : "image/png";
  if (maxSize > 0) {
    cv::Mat img = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    if (!img.empty() && std::max(img.cols, img.rows) > maxSize) {
      const double s = static_cast<double>(maxSize) / std::max(img.cols, img.rows);
      cv::Mat small;
      cv::resize(img, small,
                 cv::Size(std::max(1, static_cast<int>(std::lround(img.cols * s))),
                          std::max(1, static_cast<int>(std::lround(img.rows * s)))),
                 0, 0, cv::INTER_AREA);
      std::vector<uchar> buf;
      if (cv::imencode(".png", small, buf))
        return "data:image/png;base64," + base64(std::string(buf.begin(), buf.end()));
    }
  }
  const std::string bytes = readBytes(file);
  if (bytes.empty()) return {};
  return "data:" + mime + ";base64," + base64(bytes);
}

bool browserShows(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), ::tolower);
  return e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".webp" || e == ".gif" || e == ".bmp";
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

struct ViewInfo {
  int index = 0;
  std::string photoUrl, renderUrl, diffUrl;
  std::string note;
  io::CameraDesc camera;
};

/// Writes renders/view<i>_diff.png = |render - photo| * 4 (linear), sRGB-encoded.
bool writeDiff(const fs::path& photo, const std::string& colorSpace, const fs::path& render,
               const fs::path& out) {
  cv::Mat p =
      io::readImage(photo, colorSpace == "linear" ? io::ColorSpace::Linear : io::ColorSpace::Auto);
  cv::Mat r = io::readImage(render);
  if (r.size() != p.size()) cv::resize(r, r, p.size(), 0, 0, cv::INTER_AREA);
  cv::Mat d;
  cv::absdiff(r, p, d);
  d *= 4.0;
  cv::min(d, 1.0, d);
  io::writeImage(out, d);
  return true;
}

/// Writes viewer/twin_data.js from twin.gltf with its buffers and images as data URIs.
void writeTwinData(const fs::path& outDir, const fs::path& gltfFile, const ReportOptions& options) {
  json g = io::readJsonFile(gltfFile);
  const fs::path base = gltfFile.parent_path();
  auto resolve = [&](const std::string& uri) {
    std::string dec;
    for (size_t i = 0; i < uri.size(); ++i) {
      if (uri[i] == '%' && i + 2 < uri.size()) {
        dec += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
        i += 2;
      } else {
        dec += uri[i];
      }
    }
    return base / fs::path(dec);
  };
  if (g.contains("buffers"))
    for (auto& b : g["buffers"]) {
      if (!b.contains("uri") || b["uri"].get<std::string>().rfind("data:", 0) == 0) continue;
      const fs::path f = resolve(b["uri"].get<std::string>());
      const std::string bytes = readBytes(f);
      if (bytes.empty() && b.value("byteLength", 0) > 0)
        throw InputError(gltfFile.string(), "buffers",
                         "a readable buffer file, " + f.string() + " is missing");
      b["uri"] = "data:application/octet-stream;base64," + base64(bytes);
    }
  if (g.contains("images"))
    for (auto& im : g["images"]) {
      if (!im.contains("uri") || im["uri"].get<std::string>().rfind("data:", 0) == 0) continue;
      const fs::path f = resolve(im["uri"].get<std::string>());
      const std::string uri = imageDataUri(f, options.viewerTextureSize);
      if (uri.empty()) {
        spdlog::warn("report: {} (named by {}) is missing; the viewer shows that texture blank",
                     f.string(), gltfFile.string());
        continue;
      }
      im["uri"] = uri;
      im.erase("mimeType");
    }
  io::writeTextFile(outDir / "viewer" / "twin_data.js",
                    "// The twin's glTF (twin.gltf) with its buffer and textures embedded, for "
                    "report.html's viewer.\n"
                    "window.__psTwinGltf = " +
                        g.dump() + ";\n");
}

void copyFileAtomically(const fs::path& from, const fs::path& to) {
  io::writeAtomically(to, [&](const fs::path& tmp) {
    fs::copy_file(from, tmp, fs::copy_options::overwrite_existing);
  });
}

}  // namespace

fs::path defaultViewerDir() {
  if (const char* env = std::getenv("PHOTOSCENE_VIEWER_DIR"))
    if (fs::exists(fs::path(env) / "photoscene-viewer.js")) return env;
#ifdef PS_VIEWER_DIR
  const fs::path buildTree = PS_VIEWER_DIR;
#else
  const fs::path buildTree;
#endif
  // an installed tree's share/photoscene/viewer, else the build tree's (ps::findDataFolder)
  if (const fs::path dir = findDataFolder("viewer", buildTree);
      !dir.empty() && fs::exists(dir / "photoscene-viewer.js"))
    return dir;
  if (!buildTree.empty() && fs::exists(buildTree / "photoscene-viewer.js")) return buildTree;
  return {};
}

ReportSummary writeReport(const fs::path& outDir, const ReportOptions& options) {
  Timer timer;
  ReportSummary summary;
  const fs::path sceneFile = outDir / "scene.json";
  if (!fs::exists(sceneFile))
    throw InputError(sceneFile.string(), "",
                     "a twin folder with scene.json (the output of `photoscene run`)");
  const io::SceneDesc desc = io::readSceneJson(sceneFile);

  // ---- parts: the OBJ's usemtl names in order, else the materials files
  std::vector<std::string> parts;
  std::string partsNote;
  try {
    const io::ObjMesh obj = io::readObj(desc.geometry);
    parts = obj.materialNames;
    bool unnamed = false;
    for (int m : obj.triangleMaterial) unnamed |= m < 0;
    if (unnamed && std::find(parts.begin(), parts.end(), "default") == parts.end())
      parts.push_back("default");
  } catch (const std::exception& e) {
    partsNote = std::string("geometry not readable (") + e.what() + "); parts from materials/";
    if (fs::is_directory(outDir / "materials"))
      for (const auto& e2 : fs::directory_iterator(outDir / "materials"))
        if (e2.path().extension() == ".json") parts.push_back(e2.path().stem().string());
    std::sort(parts.begin(), parts.end());
  }
  summary.parts = static_cast<int>(parts.size());

  // ---- metrics.json (optional, possibly partial)
  json metrics = json::object();
  std::string metricsNote;
  if (fs::exists(outDir / "metrics.json")) {
    try {
      metrics = io::readJsonFile(outDir / "metrics.json");
      summary.metricsFound = metrics.is_object();
      if (!metrics.is_object()) metrics = json::object();
    } catch (const std::exception& e) {
      metricsNote = std::string("metrics.json is not readable: ") + e.what();
    }
  } else {
    metricsNote = "No metrics.json in this folder (run `photoscene eval`).";
  }
  auto metricsOfView = [&](int i) -> const json* {
    const json* vs = at(metrics, "views");
    if (!vs || !vs->is_array()) return nullptr;
    for (const auto& v : *vs)
      if (v.is_object() && v.value("view", -1) == i) return &v;
    return nullptr;
  };

  // ---- lights (rectangles for the viewer; part emitters and windows for the table)
  json emitters = json::array();
  std::map<std::string, std::string> partRole;
  try {
    std::vector<Part> partList;
    for (size_t i = 0; i < parts.size(); ++i) partList.push_back({parts[i], static_cast<int>(i)});
    const Vec3f up = desc.up.cast<float>();
    const LightSet lights =
        fs::exists(outDir / "lights.json")
            ? makeLights(io::readLightsJson(outDir / "lights.json"), Mesh(), partList, up,
                         (outDir / "lights.json").string())
            : makeLights(desc.lights, Mesh(), partList, up, sceneFile.string(), false);
    LightJsonContext jc;
    jc.parts = &partList;
    jc.baseDir = outDir;
    for (const Light* l : lights.all()) {
      for (int p : l->emittingParts()) partRole[parts[p]] = "emitter";
      for (int p : l->openingParts()) partRole[parts[p]] = "window";
      // lights with a rectangle in their entry are drawn by the viewer
      const json e = l->toJson(jc);
      if (!e.contains("center") || !e.contains("edge_u") || !e.contains("edge_v")) continue;
      const Vec3d r = l->scale().value_or(Vec3f::Ones()).cast<double>();
      emitters.push_back({{"center", e["center"]},
                          {"edge_u", e["edge_u"]},
                          {"edge_v", e["edge_v"]},
                          {"radiance", {r.x(), r.y(), r.z()}}});
    }
  } catch (const std::exception& e) {
    spdlog::warn("report: lights not readable: {}", e.what());
  }

  // ---- views: photo, render, diff
  std::vector<ViewInfo> views;
  for (size_t i = 0; i < desc.views.size(); ++i) {
    const io::ViewDesc& vd = desc.views[i];
    ViewInfo v;
    v.index = static_cast<int>(i);
    v.camera = vd.camera;
    const std::string stem = "view" + std::to_string(i);
    const fs::path render = outDir / "renders" / (stem + ".png");
    const bool havePhoto = fs::exists(vd.image);
    try {
      if (havePhoto && browserShows(vd.image)) {
        v.photoUrl = urlFor(vd.image, outDir);
      } else if (havePhoto) {
        const fs::path shown = outDir / "renders" / (stem + "_photo.png");
        if (!fs::exists(shown))
          io::writeImage(shown,
                         io::readImage(vd.image, vd.colorSpace == "linear" ? io::ColorSpace::Linear
                                                                           : io::ColorSpace::Auto));
        v.photoUrl = urlFor(shown, outDir);
      }
      if (fs::exists(render)) {
        ++summary.rendersFound;
        v.renderUrl = urlFor(render, outDir);
        const fs::path diff = outDir / "renders" / (stem + "_diff.png");
        if (!fs::exists(diff) && havePhoto) {
          writeDiff(vd.image, vd.colorSpace, render, diff);
          ++summary.diffsWritten;
        }
        if (fs::exists(diff)) v.diffUrl = urlFor(diff, outDir);
      }
    } catch (const std::exception& e) {
      v.note = e.what();
      spdlog::warn("report: view {}: {}", i, e.what());
    }
    views.push_back(v);
  }
  summary.views = static_cast<int>(views.size());

  // ---- the 3D viewer
  const fs::path gltfFile = outDir / "twin.gltf";
  if (options.viewer) {
    const fs::path viewerDir = options.viewerDir.empty() ? defaultViewerDir() : options.viewerDir;
    try {
      if (viewerDir.empty() || !fs::exists(viewerDir / "photoscene-viewer.js")) {
        summary.viewerNote =
            "The 3D viewer was not built (third_party/web/node_modules missing: run "
            "scripts/setup.sh, then rebuild).";
      } else {
        if (!fs::exists(gltfFile) && options.exportGltfIfMissing) {
          spdlog::info("report: no twin.gltf in {}; exporting it", outDir.string());
          writeTwinGltf(loadTwin(outDir), outDir);
        }
        if (!fs::exists(gltfFile)) {
          summary.viewerNote = "No twin.gltf in this folder.";
        } else {
          fs::create_directories(outDir / "viewer");
          copyFileAtomically(viewerDir / "photoscene-viewer.js",
                             outDir / "viewer" / "photoscene-viewer.js");
          if (fs::exists(viewerDir / "LICENSE-three.txt"))
            copyFileAtomically(viewerDir / "LICENSE-three.txt",
                               outDir / "viewer" / "LICENSE-three.txt");
          writeTwinData(outDir, gltfFile, options);
          summary.viewerWritten = true;
        }
      }
    } catch (const std::exception& e) {
      summary.viewerNote = std::string("The 3D viewer could not be prepared: ") + e.what();
    }
    if (!summary.viewerWritten) spdlog::warn("report: {}", summary.viewerNote);
  }

  // ================================================================ the page
  std::ostringstream h;
  const std::string title =
      "photoscene report: " + fs::absolute(outDir).lexically_normal().filename().string();
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
    << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
    << "<link rel=\"icon\" href=\"data:,\">\n"
    << "<title>" << html(title) << "</title>\n<style>" << kStyle << "</style></head><body>\n";
  h << "<header><h1>" << html(title) << "</h1><div class=\"sub\">" << views.size() << " view(s), "
    << parts.size() << " parts";
  if (const json* p = at(metrics, "preset"); p && p->is_string())
    h << ", preset " << html(p->get<std::string>());
  if (const json* t = at(metrics, "total_seconds"); t && t->is_number())
    h << ", " << fmtNum(t->get<double>(), 4) << " s in total";
  h << "</div></header>\n<main>\n";

  // 3D viewer
  h << "<section id=\"viewer-section\"><h2>Digital twin (twin.gltf)</h2>\n";
  if (summary.viewerWritten) {
    json cfg = {{"views", json::array()}, {"emitters", emitters}};
    for (const auto& v : views) {
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
    for (const auto& v : views)
      h << "<button data-view=\"" << v.index << "\">Go to input view " << v.index << "</button>";
    h << "</div>\n<div class=\"note\">Drag to orbit, scroll to zoom, right-drag to pan. Lighting "
         "in the viewer is "
         "approximate (hemisphere light plus the emitters); the renders below are the path-traced "
         "twin.</div>\n"
      << "<script type=\"application/json\" id=\"ps-viewer-config\">" << cfgText << "</script>\n";
  } else {
    h << "<p class=\"missing\">" << html(summary.viewerNote) << "</p>\n";
  }
  h << "</section>\n";

  // views
  h << "<section id=\"views\"><h2>Input views: photo, render, difference</h2><div "
       "class=\"views\">\n";
  for (const auto& v : views) {
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
    if (const json* m = metricsOfView(v.index)) {
      const json* s = at(*m, "srgb255");
      h << "<div class=\"note\">PSNR " << fmtNum(s ? num(at(*s, "psnr")) : std::nan(""))
        << " dB, SSIM " << fmtNum(s ? num(at(*s, "ssim")) : std::nan("")) << ", RMSE (sRGB 0-255) "
        << fmtNum(s ? num(at(*s, "rmse")) : std::nan("")) << "</div>";
    }
    h << "</div>\n";
  }
  if (views.empty()) h << "<p class=\"missing\">scene.json has no views.</p>";
  h << "</div></section>\n";

  // per-part table
  h << "<section id=\"parts\"><h2>Materials per part</h2>\n";
  if (!partsNote.empty()) h << "<p class=\"note\">" << html(partsNote) << "</p>";
  h << "<table><thead><tr><th>part</th><th>graph</th><th>category</th><th>maps</th><th>key "
       "parameters</th>"
       "<th>UV transform</th><th>fit view</th><th>loss</th><th>loss "
       "curve</th><th>seconds</th><th>RMSE (sRGB)</th>"
       "<th>skipped</th></tr></thead><tbody>\n";
  for (const std::string& part : parts) {
    const fs::path mf = outDir / "materials" / (part + ".json");
    json m = json::object();
    std::string note;
    if (fs::exists(mf)) {
      try {
        m = io::readJsonFile(mf);
      } catch (const std::exception& e) {
        note = e.what();
      }
    } else {
      note = "no materials file (renders gray)";
    }
    if (!m.is_object()) m = json::object();
    auto str = [&](const char* k) {
      const json* v = at(m, k);
      return v && v->is_string() ? html(v->get<std::string>()) : std::string();
    };
    h << "<tr id=\"part-" << html(part) << "\"><td><b>" << html(part) << "</b>";
    if (partRole.count(part)) h << "<br><span class=\"note\">" << partRole[part] << "</span>";
    h << "</td><td>" << str("graph") << "</td><td>" << str("category") << "</td><td class=\"maps\">";
    if (const json* maps = at(m, "maps"); maps && maps->is_object()) {
      for (const char* k : {"albedo", "normal", "roughness", "metallic"}) {
        const json* f = at(*maps, k);
        if (!f || !f->is_string()) continue;
        const std::string url = urlFor(outDir / f->get<std::string>(), outDir);
        h << "<a href=\"" << html(url) << "\"><img class=\"thumb\" src=\""
          << html(url) << "\" alt=\"" << k << "\" title=\"" << k << "\"></a> ";
      }
    } else if (const json* hom = at(m, "homogeneous")) {
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
    h << "</td><td class=\"params\">";
    if (const json* p = at(m, "params"); p && p->is_object()) {
      int n = 0;
      for (auto it = p->begin(); it != p->end() && n < options.maxParamsPerPart; ++it, ++n)
        h << html(it.key()) << " = " << paramText(it.value()) << "<br>";
      if (static_cast<int>(p->size()) > options.maxParamsPerPart)
        h << "&hellip; " << (p->size() - options.maxParamsPerPart) << " more";
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
      << fmtNum(num(path(metrics, {"parts", part.c_str(), "srgb255", "rmse"}))) << "</td><td>";
    if (const json* s = at(f, "skipped"); s && s->is_string()) h << html(s->get<std::string>());
    if (!note.empty()) h << "<span class=\"missing\">" << html(note) << "</span>";
    h << "</td></tr>\n";
  }
  h << "</tbody></table></section>\n";

  // metrics
  h << "<section id=\"metrics\"><h2>Metrics</h2>\n";
  if (!metricsNote.empty()) h << "<p class=\"missing\">" << html(metricsNote) << "</p>\n";
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
  h << "</section>\n</main>\n";
  if (summary.viewerWritten)
    h << "<script src=\"viewer/twin_data.js\"></script>\n<script "
         "src=\"viewer/photoscene-viewer.js\"></script>\n";
  h << "<script>" << kPageScript << "</script>\n</body></html>\n";
  io::writeTextFile(outDir / "report.html", h.str());
  spdlog::info(
      "report {}: {} views ({} renders, {} diffs written), {} parts, metrics {}, viewer {} "
      "({:.2f}s)",
      (outDir / "report.html").string(), summary.views, summary.rendersFound, summary.diffsWritten,
      summary.parts, summary.metricsFound ? "yes" : "no", summary.viewerWritten ? "yes" : "no",
      timer.seconds());
  return summary;
}

}  // namespace ps

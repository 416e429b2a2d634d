// Gathering the report (report_data.hpp): what a twin output folder holds, read into a
// ReportData, and the derived files the page links, written (difference images, sRGB copies of
// photos, candidate graph previews, the viewer's scripts).
#include "photoscene/core/log.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "photoscene/report/views_summary.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/graph/graph_library.hpp"
#include "photoscene/graph/preview.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/io/obj_io.hpp"
#include "photoscene/io/scene_json.hpp"
#include "photoscene/io/uri.hpp"
#include "photoscene/scene/gltf_export.hpp"
#include "photoscene/scene/scene.hpp"
#include "report_data.hpp"

namespace ps::report_detail {

namespace fs = std::filesystem;

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

namespace {

/// A relative URL (from outDir) of a file, '/'-separated and percent-encoded.
std::string urlFor(const fs::path& file, const fs::path& outDir) {
  return io::relativeUri(file, outDir);
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

// The OBJ's usemtl names in order, else the materials files' (with a note saying so).
std::vector<std::string> partNames(const fs::path& outDir, const io::SceneDesc& desc,
                                   std::string* note) {
  std::vector<std::string> parts;
  try {
    const io::ObjMesh obj = io::readObj(desc.geometry);
    parts = obj.materialNames;
    bool unnamed = false;
    for (int m : obj.triangleMaterial) unnamed |= m < 0;
    if (unnamed && std::find(parts.begin(), parts.end(), "default") == parts.end())
      parts.push_back("default");
  } catch (const std::exception& e) {
    *note = std::string("geometry not readable (") + e.what() + "); parts from materials/";
    if (fs::is_directory(outDir / "materials"))
      for (const auto& e2 : fs::directory_iterator(outDir / "materials"))
        if (e2.path().extension() == ".json") parts.push_back(e2.path().stem().string());
    std::sort(parts.begin(), parts.end());
  }
  return parts;
}

// metrics.json (optional, possibly partial): an object, else empty with a note.
json readMetrics(const fs::path& outDir, std::string* note, bool* found) {
  json metrics = json::object();
  if (!fs::exists(outDir / "metrics.json")) {
    *note = "No metrics.json in this folder (run `photoscene eval`).";
    return metrics;
  }
  try {
    metrics = io::readJsonFile(outDir / "metrics.json");
    *found = metrics.is_object();
    if (!metrics.is_object()) metrics = json::object();
  } catch (const std::exception& e) {
    *note = std::string("metrics.json is not readable: ") + e.what();
  }
  return metrics;
}

// The lights (lights.json, else scene.json's), through ps::Light: rectangles for the viewer,
// and each part's role (emitter, window) for the table.
json gatherLights(const fs::path& outDir, const io::SceneDesc& desc,
                  const std::vector<std::string>& parts,
                  std::map<std::string, std::string>* partRole) {
  json emitters = json::array();
  try {
    std::vector<Part> partList;
    for (size_t i = 0; i < parts.size(); ++i) partList.push_back({parts[i], static_cast<int>(i)});
    const Vec3f up = desc.up.cast<float>();
    const fs::path lightsFile = outDir / "lights.json";
    const LightSet lights =
        fs::exists(lightsFile)
            ? makeLights(io::readLightsJson(lightsFile), Mesh(), partList, up, lightsFile.string())
            : makeLights(desc.lights, Mesh(), partList, up, (outDir / "scene.json").string(),
                         false);
    LightJsonContext jc;
    jc.parts = &partList;
    jc.baseDir = outDir;
    for (const Light* l : lights.all()) {
      for (int p : l->emittingParts()) (*partRole)[parts[p]] = "emitter";
      for (int p : l->openingParts()) (*partRole)[parts[p]] = "window";
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
  return emitters;
}

// One input view: photo (an sRGB copy when browsers cannot show it), render, difference image.
ReportView gatherView(const fs::path& outDir, const io::ViewDesc& vd, int i,
                      ReportSummary* summary) {
  ReportView v;
  v.index = i;
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
      ++summary->rendersFound;
      v.renderUrl = urlFor(render, outDir);
      const fs::path diff = outDir / "renders" / (stem + "_diff.png");
      if (!fs::exists(diff) && havePhoto) {
        writeDiff(vd.image, vd.colorSpace, render, diff);
        ++summary->diffsWritten;
      }
      if (fs::exists(diff)) v.diffUrl = urlFor(diff, outDir);
    }
  } catch (const std::exception& e) {
    v.note = e.what();
    spdlog::warn("report: view {}: {}", i, e.what());
  }
  return v;
}

// The 3D viewer's files (viewer/): the bundled script and the twin's glTF as a script.
void prepareViewer(const fs::path& outDir, const ReportOptions& options, ReportSummary* summary) {
  const fs::path gltfFile = outDir / "twin.gltf";
  const fs::path viewerDir = options.viewerDir.empty() ? defaultViewerDir() : options.viewerDir;
  try {
    if (viewerDir.empty() || !fs::exists(viewerDir / "photoscene-viewer.js")) {
      summary->viewerNote =
          "The 3D viewer was not built (third_party/web/node_modules missing: run "
          "scripts/setup.sh, then rebuild).";
    } else {
      if (!fs::exists(gltfFile) && options.exportGltfIfMissing) {
        spdlog::info("report: no twin.gltf in {}; exporting it", outDir.string());
        writeTwinGltf(loadTwin(outDir), outDir);
      }
      if (!fs::exists(gltfFile)) {
        summary->viewerNote = "No twin.gltf in this folder.";
      } else {
        fs::create_directories(outDir / "viewer");
        copyFileAtomically(viewerDir / "photoscene-viewer.js",
                           outDir / "viewer" / "photoscene-viewer.js");
        if (fs::exists(viewerDir / "LICENSE-three.txt"))
          copyFileAtomically(viewerDir / "LICENSE-three.txt",
                             outDir / "viewer" / "LICENSE-three.txt");
        writeTwinData(outDir, gltfFile, options);
        summary->viewerWritten = true;
      }
    }
  } catch (const std::exception& e) {
    summary->viewerNote = std::string("The 3D viewer could not be prepared: ") + e.what();
  }
  if (!summary->viewerWritten) spdlog::warn("report: {}", summary->viewerNote);
}

// previews/<graph>.png: the graph at its default parameters on a lit sphere (graph/preview.hpp),
// written once per graph; empty when the graph is not in the library (or the library is not
// there).
std::string graphPreviewUrl(const fs::path& outDir, const std::string& graph,
                            const ReportOptions& options) {
  static const std::optional<GraphLibrary> library = []() -> std::optional<GraphLibrary> {
    try {
      return GraphLibrary::load();
    } catch (const std::exception& e) {
      spdlog::warn("report: no graph library for the candidates' previews: {}", e.what());
      return std::nullopt;
    }
  }();
  if (!library || options.candidatePreviewSize <= 0) return {};
  const std::vector<std::string> names = library->names();
  if (!std::binary_search(names.begin(), names.end(), graph)) return {};
  const fs::path file = outDir / "previews" / (graph + ".png");
  if (!fs::exists(file)) {
    MaterialGraph g = library->create(graph);
    PreviewOptions po;
    po.size = options.candidatePreviewSize;
    fs::create_directories(file.parent_path());
    int mapSize = 64;  // the maps at a power of two, at least the preview's size
    while (mapSize < po.size && mapSize < 1024) mapSize *= 2;
    io::writeImage(file, renderMaterialPreview(g.evaluate(mapSize), po));
  }
  return urlFor(file, outDir);
}

// A part's row: its materials file, map thumbnails, metrics and the candidate graphs.
ReportPart gatherPart(const fs::path& outDir, const std::string& name, const json& metrics,
                      const ReportOptions& options) {
  ReportPart p;
  p.name = name;
  const fs::path mf = outDir / "materials" / (name + ".json");
  if (fs::exists(mf)) {
    try {
      p.material = io::readJsonFile(mf);
    } catch (const std::exception& e) {
      p.note = e.what();
    }
  } else {
    p.note = "no materials file (renders gray)";
  }
  if (!p.material.is_object()) p.material = json::object();
  if (const json* maps = at(p.material, "maps"); maps && maps->is_object())
    for (const char* k : {"albedo", "normal", "roughness", "metallic"})
      if (const json* f = at(*maps, k); f && f->is_string())
        p.mapUrls.emplace_back(k, urlFor(outDir / f->get<std::string>(), outDir));
  if (const json* m = path(metrics, {"parts", name.c_str()})) p.metrics = *m;
  const json* graph = at(p.material, "graph");
  if (const json* cs = path(p.material, {"fit", "candidates"}); cs && cs->is_array()) {
    for (const json& c : *cs) {
      if (p.candidates.size() >= 5) break;
      const json* g = at(c, "graph");
      if (!g || !g->is_string()) continue;
      ReportCandidate rc;
      rc.graph = g->get<std::string>();
      if (const json* cat = at(c, "category"); cat && cat->is_string())
        rc.category = cat->get<std::string>();
      rc.score = num(at(c, "score"));
      if (const json* v = at(c, "votes"); v && v->is_number()) rc.votes = v->get<int>();
      rc.chosen = graph && graph->is_string() && graph->get<std::string>() == rc.graph;
      try {
        rc.previewUrl = graphPreviewUrl(outDir, rc.graph, options);
      } catch (const std::exception& e) {
        spdlog::warn("report: preview of graph {}: {}", rc.graph, e.what());
      }
      p.candidates.push_back(std::move(rc));
    }
  }
  if (const json* fs = path(p.material, {"fit", "finalists"}); fs && fs->is_array()) {
    for (const json& f : *fs) {
      const json* g = at(f, "graph");
      if (!g || !g->is_string()) continue;
      ReportFinalist rf;
      rf.graph = g->get<std::string>();
      rf.loss = num(at(f, "loss"));
      rf.contrast = num(at(f, "contrast"));
      rf.coarseContrast = num(at(f, "contrast_coarse"));
      rf.chroma = num(at(f, "chroma_spread"));
      rf.chromaOutside = num(at(f, "chroma_outside"));
      if (const json* q = at(f, "qualifies"); q && q->is_boolean()) rf.qualifies = q->get<bool>();
      rf.chosen = graph && graph->is_string() && graph->get<std::string>() == rf.graph;
      p.finalists.push_back(std::move(rf));
    }
  }
  p.photoContrast = num(path(p.material, {"fit", "photo_contrast"}));
  p.photoCoarseContrast = num(path(p.material, {"fit", "photo_contrast_coarse"}));
  p.photoChroma = num(path(p.material, {"fit", "photo_chroma_spread"}));
  // absent in folders written before the key (their scale was 2)
  if (const json* s = path(p.material, {"fit", "coarse_contrast_scale"});
      s && s->is_number_integer() && s->get<int>() > 1)
    p.coarseScale = s->get<int>();
  if (const json* r = path(p.material, {"fit", "texture_rejected"}); r && r->is_string())
    p.textureRejected = r->get<std::string>();
  if (const json* c = path(p.material, {"fit", "category_given"}); c && c->is_string())
    p.categoryGiven = c->get<std::string>();
  return p;
}

}  // namespace

ReportData gatherReport(const fs::path& outDir, const ReportOptions& options,
                        ReportSummary* summary) {
  const fs::path sceneFile = outDir / "scene.json";
  if (!fs::exists(sceneFile))
    throw InputError(sceneFile.string(), "",
                     "a twin folder with scene.json (the output of `photoscene run`)");
  const io::SceneDesc desc = io::readSceneJson(sceneFile);
  ReportData d;
  d.title = "photoscene report: " + fs::absolute(outDir).lexically_normal().filename().string();
  const std::vector<std::string> parts = partNames(outDir, desc, &d.partsNote);
  summary->parts = static_cast<int>(parts.size());
  d.metrics = readMetrics(outDir, &d.metricsNote, &summary->metricsFound);
  if (const json* p = at(d.metrics, "preset"); p && p->is_string())
    d.preset = p->get<std::string>();
  d.totalSeconds = num(at(d.metrics, "total_seconds"));
  std::map<std::string, std::string> partRole;
  d.emitters = gatherLights(outDir, desc, parts, &partRole);
  try {
    d.viewChoiceHtml = report::viewsHtml(report::summarizeViews(outDir));
  } catch (const std::exception& e) {
    d.viewChoiceNote = std::string("views table: ") + e.what();
  }
  for (size_t i = 0; i < desc.views.size(); ++i) {
    ReportView v = gatherView(outDir, desc.views[i], static_cast<int>(i), summary);
    if (const json* vs = at(d.metrics, "views"); vs && vs->is_array())
      for (const auto& m : *vs)
        if (m.is_object() && m.value("view", -1) == v.index) {
          v.metrics = m;
          break;
        }
    d.views.push_back(std::move(v));
  }
  summary->views = static_cast<int>(d.views.size());
  if (options.viewer) prepareViewer(outDir, options, summary);
  d.viewerWritten = summary->viewerWritten;
  d.viewerNote = summary->viewerNote;
  for (const std::string& name : parts) {
    ReportPart p = gatherPart(outDir, name, d.metrics, options);
    if (auto it = partRole.find(name); it != partRole.end()) p.role = it->second;
    d.parts.push_back(std::move(p));
  }
  return d;
}

}  // namespace ps::report_detail

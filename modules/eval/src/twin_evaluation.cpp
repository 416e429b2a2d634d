#include "photoscene/eval/twin_evaluation.hpp"

#include <utility>
#include "photoscene/core/log.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>

#include "photoscene/align/align.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/io/json.hpp"
#include "photoscene/io/scene_json.hpp"
#include "photoscene/raytrace/gbuffer.hpp"
#include "photoscene/raytrace/render_twin.hpp"
#include "photoscene/scene/material.hpp"
#include "photoscene/scene/scene.hpp"

namespace ps::eval {

namespace fs = std::filesystem;

bool EvalOptions::IsValid(std::string* error) const {
  if (spp < 1 || spp > 1 << 16) {
    if (error) *error = "spp must be in [1, 65536], got " + std::to_string(spp);
    return false;
  }
  return true;
}

std::string colorSpaceDefinition(ColorSpace space) {
  if (space == ColorSpace::Srgb255)
    return "255 * sRGB_OETF(clamp(linear, 0, 1)), unquantized: what an 8-bit display shows (the "
           "paper's scale); "
           "PSNR peak 255, SSIM dynamic range 255, GMSD c = 170";
  return "scene-linear RGB as rendered (render x exposure) and as decoded from the photo or read "
         "from EXR, "
         "unclamped; PSNR peak 1, SSIM dynamic range 1, GMSD c = 170 / 255^2";
}

namespace {

ImageScore score(const cv::Mat& render, const cv::Mat& reference) {
  ImageScore s;
  s.srgb255 = compareImages(render, reference, ColorSpace::Srgb255);
  s.linear = compareImages(render, reference, ColorSpace::Linear);
  return s;
}

/// The first existing file among `stem` + extensions.
std::optional<fs::path> firstImage(const fs::path& stem) {
  for (const char* ext : {".exr", ".hdr", ".png"}) {
    fs::path p = stem;
    p += ext;
    if (fs::is_regular_file(p)) return p;
  }
  return std::nullopt;
}

/// Parses a lights file in our lights.json form, or nullopt (with the reason) when it is not.
std::optional<io::LightsFileDesc> tryLights(const fs::path& p, std::string* why = nullptr) {
  if (!fs::is_regular_file(p)) return std::nullopt;
  try {
    // Another program's lights description may share some keys (blender-room's lights_relit.json
    // has an "environment"): only a file with our "emitters" list counts.
    const nlohmann::json raw = io::readJsonFile(p);
    if (!raw.is_object() || !raw.contains("emitters") || !raw["emitters"].is_array() ||
        raw["emitters"].empty()) {
      if (why) *why = p.string() + ": emitters: expected a non-empty list (lights.json form)";
      return std::nullopt;
    }
    return io::readLightsJson(p);
  } catch (const InputError& e) {
    if (why) *why = e.what();
    return std::nullopt;
  }
}

double geometricMean(const std::vector<double>& v) {
  if (v.empty()) return 1.0;
  double s = 0;
  for (double x : v) s += std::log(std::max(x, 1e-12));
  return std::exp(s / v.size());
}

void requireRadiance(const Scene& scene, const std::string& file) {
  const std::vector<const Light*> lights = scene.lights.all();
  for (size_t i = 0; i < lights.size(); ++i)
    if (!lights[i]->scale())
      throw InputError(
          file, "emitters[" + std::to_string(i) + "].radiance",
          "a radiance for emitter '" + lights[i]->label() + "' (the twin must be renderable)");
  if (lights.empty()) throw InputError(file, "emitters", "at least one emitter or an environment");
}

Vec3d ratio(const Vec3d& relit, const Vec3d& original) {
  Vec3d r;
  for (int c = 0; c < 3; ++c) r[c] = original[c] > 1e-9 ? relit[c] / original[c] : 1.0;
  return r;
}

/// The twin's lights for a relit ground truth (see the header: relative when the photo's lights
/// are known, else the relit emitters themselves).
LightSet relitLights(const Scene& twin, const GroundTruthRender& gt,
                     std::vector<std::string>* notes) {
  const io::LightsFileDesc relit = io::readLightsJson(*gt.lights);
  std::optional<io::LightsFileDesc> original;
  if (gt.photoLights) original = tryLights(*gt.photoLights);
  if (!original) return makeLights(relit, twin.mesh, twin.parts, twin.up, gt.lights->string());

  const LightSet relitSet = makeLights(relit, twin.mesh, twin.parts, twin.up, gt.lights->string());
  LightSet originalSet;
  try {
    originalSet = makeLights(*original, twin.mesh, twin.parts, twin.up, gt.photoLights->string());
  } catch (const InputError& e) {  // e.g. an emitter part the twin does not have
    if (notes)
      notes->push_back(gt.name + ": the photo's lights do not fit the twin (" + e.what() +
                       "); relit with the relit lights themselves");
    return relitSet;
  }
  // Per relit light: its ratio to the same light under the photo's lights (ps::matchLight).
  const std::vector<const Light*> relitAll = relitSet.all(),
                                  originalAll = std::as_const(originalSet).all();
  std::vector<Vec3d> ratios;
  Vec3d mean = Vec3d::Zero();
  int counted = 0;
  for (const Light* l : relitAll) {
    const int j = matchLight(*l, originalAll);
    Vec3d r = Vec3d::Ones();
    const std::optional<Vec3f> s = l->scale();
    const std::optional<Vec3f> s0 = j >= 0 ? originalAll[j]->scale() : std::nullopt;
    if (s && s0) {
      r = ratio(s->cast<double>(), s0->cast<double>());
      // the mean, for twin lights that match none, is over the emitters (not the daylight)
      if (!l->isInfinite()) mean += r, ++counted;
    }
    ratios.push_back(r);
  }
  if (counted > 0)
    mean /= counted;
  else
    mean = Vec3d::Ones();

  LightSet set = twin.lights;
  int unmatched = 0;
  for (Light* l : set.all()) {
    const int j = matchLight(*l, relitAll);
    // an infinite light the relit file does not have keeps its scale
    if (j < 0 && l->isInfinite()) continue;
    const Vec3d r = j >= 0 ? ratios[j] : mean;
    if (j < 0) ++unmatched;
    if (const std::optional<Vec3f> s = l->scale()) l->setScale(s->cwiseProduct(r.cast<float>()));
  }
  if (unmatched > 0 && notes)
    notes->push_back(gt.name + ": " + std::to_string(unmatched) +
                     " twin emitter(s) matched no relit emitter; scaled by the mean ratio");
  return set;
}

std::string relativeTo(const fs::path& p, const fs::path& base) {
  const fs::path r = p.lexically_relative(base);
  return r.empty() ? p.string() : r.generic_string();
}

}  // namespace

std::vector<GroundTruthRender> findGroundTruth(const fs::path& caseDir, int numViews,
                                               std::vector<std::string>* notes) {
  std::vector<GroundTruthRender> found;
  const fs::path gtDir = caseDir / "gt";
  if (!fs::is_directory(gtDir)) return found;
  const std::regex pattern(R"((novel|relit)(\d+)\.(exr|hdr|png))");
  std::map<std::string, fs::path> names;  // name -> stem, sorted
  for (const auto& entry : fs::directory_iterator(gtDir)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (entry.is_regular_file() && std::regex_match(file, m, pattern))
      names[m[1].str() + m[2].str()] = gtDir / (m[1].str() + m[2].str());
  }
  std::optional<fs::path> photoLights;
  for (const fs::path& p : {gtDir / "twin" / "lights.json", caseDir / "lights_gt.json"})
    if (tryLights(p)) {
      photoLights = p;
      break;
    }
  for (const auto& [name, stem] : names) {
    GroundTruthRender gt;
    gt.name = name;
    gt.image = *firstImage(stem);
    const bool novel = name.rfind("novel", 0) == 0;
    const std::string k = name.substr(5);
    gt.kind = novel ? GroundTruthRender::Kind::Novel : GroundTruthRender::Kind::Relit;
    const fs::path cam = caseDir / "cameras" / (name + ".json");
    if (fs::is_regular_file(cam)) gt.camera = cam;
    if (novel) {
      if (!gt.camera) {
        if (notes) notes->push_back(name + ": skipped, no " + cam.string());
        continue;
      }
    } else {
      std::string why;
      for (const fs::path& p :
           {caseDir / ("lights_relit" + k + ".json"), caseDir / "lights_relit.json",
            gtDir / "twin" / ("lights_relit" + k + ".json"),
            gtDir / "twin" / "lights_relit.json"}) {
        std::string w;
        if (tryLights(p, &w)) {
          gt.lights = p;
          break;
        }
        if (!w.empty() && why.empty()) why = w;
      }
      if (!gt.lights) {
        if (notes)
          notes->push_back(name + ": skipped, no lights_relit.json in lights.json form" +
                           (why.empty() ? "" : " (" + why + ")"));
        continue;
      }
      gt.photoLights = photoLights;
      gt.view = 0;
      (void)numViews;
    }
    found.push_back(gt);
  }
  return found;
}

TwinEvaluation evaluateTwin(const fs::path& outDir, const fs::path& scenePath,
                            const EvalOptions& options) {
  Timer timer;
  std::string err;
  if (!options.IsValid(&err)) throw InputError("command line", "eval options", err);
  if (!fs::is_directory(outDir))
    throw InputError(outDir.string(), "",
                     "a twin output folder (with scene.json, lights.json, materials/)");
  TwinEvaluation result;
  const Scene input = loadScene(scenePath);  // photos and segments
  Twin twin = loadTwin(outDir, false);
  result.preset = twin.scene.desc.options.preset;
  const std::string lightsFile = fs::exists(outDir / "lights.json")
                                     ? (outDir / "lights.json").string()
                                     : (outDir / "scene.json").string();
  requireRadiance(twin.scene, lightsFile);
  if (twin.scene.views.size() != input.views.size())
    throw InputError((outDir / "scene.json").string(), "views",
                     std::to_string(input.views.size()) + " views as in " + scenePath.string() +
                         ", got " + std::to_string(twin.scene.views.size()));

  const PathTracer tracer(twin.scene, twin.materials);
  RenderOptions ro;
  ro.spp = options.spp;
  ro.seed = options.seed;

  // Parts that carry no material: windows and emitters.
  std::vector<uint8_t> noMaterial(twin.scene.parts.size(), 0);
  for (int p : twin.scene.lights.openingParts())
    if (p >= 0 && p < static_cast<int>(noMaterial.size())) noMaterial[p] = 1;
  for (int p : twin.scene.lights.emittingParts())
    if (p >= 0 && p < static_cast<int>(noMaterial.size())) noMaterial[p] = 1;

  std::map<std::string, PartScore> bestPart;
  for (size_t i = 0; i < input.views.size(); ++i) {
    const View& view = input.views[i];
    const Camera& camera = view.camera;
    if (twin.scene.views[i].camera.width() != camera.width() ||
        twin.scene.views[i].camera.height() != camera.height())
      throw InputError(
          (outDir / "scene.json").string(), "views[" + std::to_string(i) + "].camera",
          "the size of the photo of " + scenePath.string() + " view " + std::to_string(i));
    const double exposure = twin.exposure[i];
    ViewScore vs;
    vs.view = static_cast<int>(i);
    vs.image = relativeTo(view.imagePath, input.desc.baseDir);
    cv::Mat exposed;  // the render times exposure[i], compared with the photo
    const fs::path saved = outDir / "renders" / ("view" + std::to_string(i) + ".exr");
    if (options.useSavedRenders && fs::is_regular_file(saved)) {
      exposed =
          io::readImage(saved);  // written with the exposure applied, as `photoscene render OUT`
      if (exposed.size() != view.photo.size()) {
        result.notes.push_back(saved.string() + " is not of the photo's size: rendered again");
        exposed.release();
      } else {
        vs.render = "renders/view" + std::to_string(i) + ".exr";
        spdlog::info("eval: view {}: {} scored as written (not rendered again)", i, vs.render);
      }
    }
    if (exposed.empty()) {
      Timer t;
      exposed = renderTwinView(tracer, camera, ro, exposure, nullptr, options.denoise);
      vs.render = "path tracer, " + std::to_string(options.spp) + " spp" +
                  (options.denoise ? ", denoised" : "");
      spdlog::info("eval: rendered view {} ({}x{}, {} spp) in {:.1f}s", i, camera.width(),
                   camera.height(), options.spp, t.seconds());
    }
    vs.score = score(exposed, view.photo);
    result.views.push_back(vs);

    if (!options.parts) continue;
    GBufferOptions go;
    go.coverageSamples = 1;
    const GBuffer gb = renderGBuffer(tracer, camera, go);
    const std::map<int, cv::Mat> geoMasks = align::partMasks(gb.partId);
    // The photo's regions, in the twin's part ids (mapped by name from the input scene's).
    cv::Mat labels;
    std::map<int, int> pinned;
    if (!view.segments.empty()) {
      labels = view.segments;
      for (const auto& [label, part] : view.segmentParts) {
        const int id = twin.scene.partId(input.parts[part].name);
        if (id >= 0) pinned[label] = id;
      }
    } else {
      labels = align::proposeRegions(view.photo, geoMasks, &pinned);
    }
    const align::MatchResult match = align::matchRegions(labels, geoMasks, pinned);
    for (const auto& [part, photoMask] : match.photoMasks) {
      if (part < 0 || part >= static_cast<int>(noMaterial.size()) || noMaterial[part]) continue;
      const auto geo = geoMasks.find(part);
      if (geo == geoMasks.end()) continue;
      const align::AlignedPart aln = align::alignPart(part, geo->second, photoMask, {exposed});
      const int pixels = cv::countNonZero(aln.mask);
      const std::string& name = twin.scene.parts[part].name;
      auto it = bestPart.find(name);
      if (pixels == 0 || (it != bestPart.end() && it->second.pixels >= pixels)) continue;
      PartScore ps;
      ps.part = name;
      ps.view = static_cast<int>(i);
      ps.pixels = pixels;
      ps.rmseSrgb255 = rmse(aln.buffers[0], view.photo, ColorSpace::Srgb255, aln.mask);
      ps.rmseLinear = rmse(aln.buffers[0], view.photo, ColorSpace::Linear, aln.mask);
      bestPart[name] = ps;
    }
  }
  for (auto& [name, ps] : bestPart) result.parts.push_back(ps);

  if (options.groundTruth) {
    const fs::path caseDir = input.desc.baseDir;
    const double meanExposure = geometricMean(twin.exposure);
    for (const GroundTruthRender& gt :
         findGroundTruth(caseDir, static_cast<int>(input.views.size()), &result.notes)) {
      const cv::Mat reference = io::readImage(gt.image);
      Camera camera = gt.camera ? Camera::fromDesc(io::readCameraJson(*gt.camera))
                                : input.views[gt.view].camera;
      if (camera.width() != reference.cols || camera.height() != reference.rows) {
        result.notes.push_back(gt.name + ": camera resized to the reference's " +
                               std::to_string(reference.cols) + "x" +
                               std::to_string(reference.rows));
        camera = camera.resized(reference.cols, reference.rows);
      }
      Timer t;
      cv::Mat render;
      if (gt.kind == GroundTruthRender::Kind::Novel) {
        render = renderTwinView(tracer, camera, ro, meanExposure, nullptr, options.denoise);
        result.novel.push_back({gt.name, score(render, reference)});
      } else {
        Scene relit = twin.scene;
        relit.lights = relitLights(twin.scene, gt, &result.notes);
        requireRadiance(relit, gt.lights->string());
        const PathTracer relitTracer(relit, twin.materials);
        const double e = gt.camera ? meanExposure : twin.exposure[gt.view];
        render = renderTwinView(relitTracer, camera, ro, e, nullptr, options.denoise);
        result.relit.push_back({gt.name, score(render, reference)});
      }
      spdlog::info("eval: {} ({}x{}, {} spp{}) in {:.1f}s", gt.name, camera.width(),
                   camera.height(), options.spp, options.denoise ? ", denoised" : "", t.seconds());
    }
  }
  result.seconds = timer.seconds();
  return result;
}

namespace {

nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json metricsJson(const ImageMetrics& m) {
  return {{"rmse", number(m.rmse)},
          {"psnr", number(m.psnr)},
          {"ssim", number(m.ssim)},
          {"gmsd", number(m.gmsd)}};
}

}  // namespace

void writeMetricsJson(const fs::path& outDir, const TwinEvaluation& e,
                      const std::map<std::string, double>& stageSeconds, const std::string& preset,
                      double totalSeconds) {
  const fs::path file = outDir / "metrics.json";
  nlohmann::json old = nlohmann::json::object();
  if (fs::exists(file)) {
    try {
      old = io::readJsonFile(file);
      if (!old.is_object()) old = nlohmann::json::object();
    } catch (const InputError& err) {
      spdlog::warn("metrics.json: existing file not readable, replaced ({})", err.what());
      old = nlohmann::json::object();
    }
  }
  nlohmann::json j = old;
  j["color_spaces"] = {{"srgb255", colorSpaceDefinition(ColorSpace::Srgb255)},
                       {"linear", colorSpaceDefinition(ColorSpace::Linear)}};
  nlohmann::json views = nlohmann::json::array();
  for (const ViewScore& v : e.views)
    views.push_back({{"view", v.view},
                     {"image", v.image},
                     {"srgb255", metricsJson(v.score.srgb255)},
                     {"linear", metricsJson(v.score.linear)}});
  j["views"] = views;
  nlohmann::json parts = nlohmann::json::object();
  for (const PartScore& p : e.parts)
    parts[p.part] = {{"view", p.view},
                     {"pixels", p.pixels},
                     {"srgb255", {{"rmse", number(p.rmseSrgb255)}}},
                     {"linear", {{"rmse", number(p.rmseLinear)}}}};
  j["parts"] = parts;
  for (const auto& [key, list] : {std::pair{"novel", &e.novel}, std::pair{"relit", &e.relit}}) {
    nlohmann::json arr = nlohmann::json::array();
    for (const GroundTruthScore& g : *list)
      arr.push_back({{"name", g.name},
                     {"srgb255", metricsJson(g.score.srgb255)},
                     {"linear", metricsJson(g.score.linear)}});
    j[key] = arr;
  }
  if (!stageSeconds.empty()) {
    nlohmann::json stages = nlohmann::json::object();
    double sum = 0;
    for (const auto& [name, s] : stageSeconds) {
      stages[name] = number(s);
      if (std::isfinite(s)) sum += s;
    }
    j["stages"] = stages;
    j["total_seconds"] = number(std::isnan(totalSeconds) ? sum : totalSeconds);
  } else {
    if (!j.contains("stages")) j["stages"] = nlohmann::json::object();
    if (!std::isnan(totalSeconds))
      j["total_seconds"] = number(totalSeconds);
    else if (!j.contains("total_seconds"))
      j["total_seconds"] = nullptr;
  }
  if (!preset.empty())
    j["preset"] = preset;
  else if (!j.contains("preset"))
    j["preset"] = e.preset.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.preset);
  io::writeJsonFile(file, j);
}

}  // namespace ps::eval

// The inputs of a run: loading and checking them (Context::load), and reading them as declared
// (Reads, stage.hpp).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "photoscene/core.hpp"
#include "photoscene/core/memory.hpp"
#include "photoscene/io.hpp"
#include "photoscene/select.hpp"
#include "runner.hpp"
#include "stage.hpp"

namespace ps::pipeline {

namespace {

fs::path defaultBankCache() {
  if (const char* d = std::getenv("PS_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return fs::path(d) / "photoscene";
  if (const char* d = std::getenv("HOME"); d && *d) return fs::path(d) / ".cache/photoscene";
  return fs::temp_directory_path() / "photoscene-cache";
}

}  // namespace

const std::vector<std::string>& optionNames() {
  static const std::vector<std::string> names = {
      "preset",   "texture_size", "work_width", "mean_albedo", "render_spp", "max_fit_iterations",
      "baseline", "write_gltf",   "library",    "ground_truth"};
  return names;
}

// ---------------------------------------------------------------- loading the inputs

std::unique_ptr<Context> Context::load(const PipelineOptions& options) {
  auto ctx = std::make_unique<Context>();
  RunInputs& in = ctx->in_;
  in.options = options;
  if (in.options.bankCache.empty()) in.options.bankCache = defaultBankCache();
  const PipelineOptions& o = in.options;
  if (o.textureSize < 4 || o.textureSize > 16384)
    throw InputError("--texture-size", "", fmt::format("expected 4..16384, got {}", o.textureSize));
  in.scene = loadScene(o.scene);
  in.preset = o.preset.value_or(in.scene.desc.options.preset);
  if (in.preset != "fast" && in.preset != "balanced" && in.preset != "paper")
    throw InputError(o.scene.string(), "options.preset",
                     "expected fast, balanced or paper, got '" + in.preset + "'");
  in.library = std::make_unique<GraphLibrary>(GraphLibrary::load());
  for (const auto& [name, part] : in.scene.desc.parts)
    if (part.graph) {
      const std::vector<std::string> names = in.library->names();
      if (!std::binary_search(names.begin(), names.end(), *part.graph))
        throw InputError(o.scene.string(), "parts." + name + ".graph",
                         "expected a graph of the library (`photoscene graphs --list`), got '" +
                             *part.graph + "'");
    }
  in.bankName = ExemplarBank::cacheFileName(*in.library, {});
  in.seed = in.scene.desc.options.seed;
  in.budget = PresetBudget::of(in.preset);
  in.fitOptions = PartFitOptions::preset(in.preset);
  const Scene& scene = in.scene;
  for (size_t k = 0; k < scene.lights.area.size(); ++k)
    if (!scene.lights.area[k].radiance) in.freeLights.push_back(static_cast<int>(k));
  // views at the working resolution
  for (const View& input : scene.views) {
    ViewInput w;
    const int width = std::min(input.camera.width(), std::max(16, o.workWidth));
    const int height = std::max(1, static_cast<int>(std::lround(double(input.camera.height()) *
                                                                width / input.camera.width())));
    w.camera = input.camera.resized(width, height);
    if (width == input.photo.cols && height == input.photo.rows)
      w.photo = input.photo;
    else
      cv::resize(input.photo, w.photo, cv::Size(width, height), 0, 0, cv::INTER_AREA);
    if (!input.segments.empty())
      cv::resize(input.segments, w.labels, w.photo.size(), 0, 0, cv::INTER_NEAREST);
    in.views.push_back(std::move(w));
  }
  // the units: one work record per view and per part
  ctx->views.resize(scene.views.size());
  for (const Part& part : scene.parts) {
    PartWork p;
    p.id = part.id;
    p.name = part.name;
    ctx->parts.push_back(std::move(p));
  }
  return ctx;
}

void Context::applyLights(const std::vector<Vec3d>& intensity) {
  LightSet& lights = in_.scene.lights;
  for (size_t i = 0; i < in_.freeLights.size() && i < intensity.size(); ++i)
    lights.area[in_.freeLights[i]].radiance = intensity[i].cast<float>();
  if (lights.environment && intensity.size() == in_.freeLights.size() + 1)
    lights.environment->radiance = intensity.back().cast<float>();
}

std::string Context::describe() const {
  const Scene& scene = in_.scene;
  const PipelineOptions& o = in_.options;
  return fmt::format(
      "{} ({} views, {} parts, {} area lights{}), preset {}{}", o.scene.string(),
      scene.views.size(), scene.parts.size(), scene.lights.area.size(),
      scene.lights.environment ? " + environment" : "", in_.preset,
      o.baseline == Baseline::None ? "" : fmt::format(", baseline {}", baselineName(o.baseline)));
}

void Context::finishResult() {
  const Scene& scene = in_.scene;
  result.out = in_.options.out;
  result.preset = in_.preset;
  result.totalSeconds = clock.seconds();
  for (const AreaLight& l : scene.lights.area) {
    result.lightNames.push_back(l.name);
    result.lightRadiance.push_back(l.radiance.value_or(Vec3f::Zero()).cast<double>());
  }
  if (scene.lights.environment) {
    result.lightNames.push_back("environment");
    result.lightRadiance.push_back(scene.lights.environment->radiance.cast<double>());
  }
  result.exposure = exposure;
  result.peakMemoryMiB = peakMemoryMiB();
}

cv::Mat partPhoto(const cv::Mat& photo, const ViewWork& view, int part) {
  cv::Mat out;
  cv::warpAffine(photo, out, cv::Mat(view.warp.at(part)), photo.size(), cv::INTER_LINEAR,
                 cv::BORDER_REFLECT);
  return out;
}

// ---------------------------------------------------------------- reading them as declared

Reads::Reads(const Context& ctx, const StageDecl& decl, int unit)
    : ctx_(ctx), decl_(decl), unit_(unit) {}

void Reads::need(std::string_view sceneKey, int view, int part) const {
  bool declared = false;
  for (const std::string& d : decl_.scene) declared = declared || keyCovers(d, sceneKey);
  if (!declared)
    throw Exception(fmt::format("stage {} reads scene.json key '{}' without declaring it",
                                decl_.name, sceneKey),
                    __FILE__, __LINE__, __func__);
  if (unit_ < 0) return;  // a stage's finish step reads every unit
  if (decl_.unit == Unit::View && view >= 0 && view != unit_)
    throw Exception(
        fmt::format("stage {} (view {}) reads view {}: a per-view stage reads only its own view",
                    decl_.name, unit_, view),
        __FILE__, __LINE__, __func__);
  if (decl_.unit == Unit::Part && part >= 0 && part != unit_)
    throw Exception(
        fmt::format("stage {} (part {}) reads part {}: a per-part stage reads only its own part",
                    decl_.name, unit_, part),
        __FILE__, __LINE__, __func__);
}

void Reads::needOption(std::string_view option) const {
  if (std::find(decl_.options.begin(), decl_.options.end(), option) == decl_.options.end())
    throw Exception(
        fmt::format("stage {} reads option '{}' without declaring it", decl_.name, option),
        __FILE__, __LINE__, __func__);
}

const Scene& Reads::sceneGeometry() const {
  for (const char* k : {"geometry", "up", "lights.area", "lights.auto_ceiling_spacing"}) need(k);
  return ctx_.in_.scene;
}

const Scene& Reads::litScene() const {
  for (const char* k : {"geometry", "up", "lights"}) need(k);
  return ctx_.in_.scene;
}

std::vector<int> Reads::emitterParts() const {
  need("lights.area[].part");
  need("geometry");
  std::vector<int> parts;
  for (const AreaLight& l : ctx_.in_.scene.lights.area)
    if (l.kind == AreaLight::Kind::Part && l.partId >= 0) parts.push_back(l.partId);
  return parts;
}

std::vector<int> Reads::windowParts() const {
  need("lights.environment.window_parts");
  need("geometry");
  const auto& env = ctx_.in_.scene.lights.environment;
  return env ? env->windowParts : std::vector<int>();
}

const std::vector<int>& Reads::freeLights() const {
  need("lights.area");
  return ctx_.in_.freeLights;
}

const Camera& Reads::camera(int view) const {
  need("views[].camera", view);
  needOption("work_width");
  return ctx_.in_.views.at(view).camera;
}

const cv::Mat& Reads::photo(int view) const {
  for (const char* k : {"views[].image", "views[].color_space", "views[].camera"}) need(k, view);
  needOption("work_width");
  return ctx_.in_.views.at(view).photo;
}

const cv::Mat& Reads::labels(int view) const {
  need("views[].segments", view);
  photo(view);  // resized to the photo's size
  return ctx_.in_.views.at(view).labels;
}

const std::map<int, int>& Reads::segmentParts(int view) const {
  need("views[].segment_parts", view);
  need("geometry");  // part names to ids
  return ctx_.in_.scene.views.at(view).segmentParts;
}

namespace {
const io::PartDesc* partDesc(const Scene& scene, const std::string& name) {
  const auto it = scene.desc.parts.find(name);
  return it == scene.desc.parts.end() ? nullptr : &it->second;
}
}  // namespace

const std::optional<std::string>& Reads::partGraph(int part) const {
  static const std::optional<std::string> none;
  need("parts.{}.graph", -1, part);
  const io::PartDesc* d = partDesc(ctx_.in_.scene, ctx_.parts.at(part).name);
  return d ? d->graph : none;
}

const std::optional<io::HomogeneousDesc>& Reads::partFixed(int part) const {
  static const std::optional<io::HomogeneousDesc> none;
  need("parts.{}.fixed", -1, part);
  const io::PartDesc* d = partDesc(ctx_.in_.scene, ctx_.parts.at(part).name);
  return d ? d->fixed : none;
}

bool Reads::partSkip(int part) const {
  need("parts.{}.skip", -1, part);
  const io::PartDesc* d = partDesc(ctx_.in_.scene, ctx_.parts.at(part).name);
  return d && d->skip;
}

uint64_t Reads::seed() const {
  need("options.seed");
  return ctx_.in_.seed;
}

const fs::path& Reads::sceneFile() const {
  need("");
  return ctx_.in_.options.scene;
}

const fs::path& Reads::evalScene() const {
  need("");
  needOption("ground_truth");
  return ctx_.in_.options.scene;
}

const Scene& Reads::wholeScene() const {
  need("");
  return ctx_.in_.scene;
}

int Reads::viewCount() const {
  return static_cast<int>(ctx_.in_.views.size());
}

const std::string& Reads::preset() const {
  needOption("preset");
  return ctx_.in_.preset;
}

const PresetBudget& Reads::budget() const {
  needOption("preset");
  return ctx_.in_.budget;
}

int Reads::renderSpp() const {
  needOption("preset");
  needOption("render_spp");
  return ctx_.in_.options.renderSpp.value_or(ctx_.in_.budget.renderSpp);
}

const PartFitOptions& Reads::fitOptions() const {
  needOption("preset");
  return ctx_.in_.fitOptions;
}

std::optional<int> Reads::maxFitIterations() const {
  needOption("max_fit_iterations");
  return ctx_.in_.options.maxFitIterations;
}

int Reads::textureSize() const {
  needOption("texture_size");
  return ctx_.in_.options.textureSize;
}

double Reads::meanAlbedo() const {
  needOption("mean_albedo");
  return ctx_.in_.options.meanAlbedo;
}

Baseline Reads::baseline() const {
  needOption("baseline");
  return ctx_.in_.options.baseline;
}

bool Reads::writeGltf() const {
  needOption("write_gltf");
  return ctx_.in_.options.writeGltf;
}

const GraphLibrary& Reads::library() const {
  needOption("library");
  return *ctx_.in_.library;
}

const std::string& Reads::bankName() const {
  needOption("library");
  return ctx_.in_.bankName;
}

const fs::path& Reads::bankCache() const {
  return ctx_.in_.options.bankCache;
}

const fs::path& Reads::out() const {
  return ctx_.in_.options.out;
}

fs::path Reads::outFile(const std::string& name) const {
  if (std::find(decl_.outputs.begin(), decl_.outputs.end(), name) == decl_.outputs.end())
    throw Exception(
        fmt::format("stage {} reads output file '{}' without declaring it", decl_.name, name),
        __FILE__, __LINE__, __func__);
  return ctx_.in_.options.out / name;
}

}  // namespace ps::pipeline

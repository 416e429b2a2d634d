// The context of a run: its inputs loaded and checked (Context::load), the lights the lights
// stages write into the scene, and the run's result.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "photoscene/core.hpp"
#include "photoscene/core/memory.hpp"
#include "photoscene/io.hpp"
#include "photoscene/select.hpp"
#include "stage.hpp"

namespace ps {

namespace {

// The categories the library has graphs of, in the spec's order, comma-separated.
std::string libraryCategories(const GraphLibrary& library) {
  std::string out;
  for (const std::string& c : materialCategories())
    if (!library.namesInCategory(c).empty()) out += (out.empty() ? "" : ", ") + c;
  return out;
}

}  // namespace

void checkPartSettings(const io::SceneDesc& scene, const GraphLibrary& library) {
  const std::vector<std::string> names = library.names();
  for (const auto& [name, part] : scene.parts) {
    if (part.graph && !std::binary_search(names.begin(), names.end(), *part.graph))
      throw InputError(scene.file.string(), "parts." + name + ".graph",
                       "expected a graph of the library (`photoscene graphs --list`), got '" +
                           *part.graph + "'");
    if (!part.category) continue;
    if (library.namesInCategory(*part.category).empty())
      throw InputError(scene.file.string(), "parts." + name + ".category",
                       "expected a category with graphs in the library (" +
                           libraryCategories(library) + "), got '" + *part.category + "'");
    if (part.graph && library.get(*part.graph).category() != *part.category)
      throw InputError(scene.file.string(), "parts." + name + ".category",
                       "expected the category of parts." + name + ".graph ('" + *part.graph +
                           "' is " + library.get(*part.graph).category() + "), got '" +
                           *part.category + "'");
  }
}

}  // namespace ps

namespace ps::pipeline {

namespace {

// What the user asked for, checked before anything is written: the preset, and what `parts`
// asks of the library (the texture size is checked before the scene is read).
void checkPresetAndGraphs(const RunInputs& in) {
  if (in.preset != "fast" && in.preset != "balanced" && in.preset != "paper")
    throw InputError(in.options.scene.string(), "options.preset",
                     "expected fast, balanced or paper, got '" + in.preset + "'");
  checkPartSettings(in.scene.desc, *in.library);
}

// A view at the working resolution (`workWidth` pixels across, never enlarged).
ViewInput workingView(const View& input, int workWidth) {
  ViewInput w;
  const int width = std::min(input.camera.width(), std::max(16, workWidth));
  const int height = std::max(1, static_cast<int>(std::lround(double(input.camera.height()) *
                                                              width / input.camera.width())));
  w.camera = input.camera.resized(width, height);
  w.clips = input.imagePath.empty() || !fs::exists(input.imagePath) ||
            !io::readImageInfo(input.imagePath).isFloat;
  if (width == input.photo.cols && height == input.photo.rows)
    w.photo = input.photo;
  else
    cv::resize(input.photo, w.photo, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  if (!input.segments.empty())
    cv::resize(input.segments, w.labels, w.photo.size(), 0, 0, cv::INTER_NEAREST);
  return w;
}

}  // namespace

std::unique_ptr<Context> Context::load(const PipelineOptions& options) {
  auto ctx = std::make_unique<Context>();
  RunInputs& in = ctx->in_;
  in.options = options;
  if (in.options.bankCache.empty()) in.options.bankCache = defaultBankCache();
  if (options.textureSize < 4 || options.textureSize > 16384)
    throw InputError("--texture-size", "",
                     fmt::format("expected 4..16384, got {}", options.textureSize));
  if (options.incidentSamples && (*options.incidentSamples < 1 || *options.incidentSamples > 4096))
    throw InputError("PipelineOptions", "incidentSamples",
                     fmt::format("expected 1..4096 path samples per bin, got {}",
                                 *options.incidentSamples));
  if (options.incidentDirectSamples &&
      (*options.incidentDirectSamples < 0 || *options.incidentDirectSamples > 4096))
    throw InputError("PipelineOptions", "incidentDirectSamples",
                     fmt::format("expected 0..4096 light samples per light, got {}",
                                 *options.incidentDirectSamples));
  in.scene = loadScene(options.scene);
  in.preset = options.preset.value_or(in.scene.desc.options.preset);
  in.library = std::make_unique<GraphLibrary>(GraphLibrary::load());
  checkPresetAndGraphs(in);
  in.bankName = ExemplarBank::cacheFileName(*in.library, {});
  in.seed = in.scene.desc.options.seed;
  in.budget = PresetBudget::of(in.preset);
  in.fitOptions = PartFitOptions::preset(in.preset);
  in.freeLights = in.scene.lights.fittedLights();
  for (const View& input : in.scene.views)
    in.views.push_back(workingView(input, options.workWidth));
  // the units: one work record per view and per part
  ctx->views.resize(in.scene.views.size());
  for (const Part& part : in.scene.parts) {
    PartWork p;
    p.id = part.id;
    p.name = part.name;
    ctx->parts.push_back(std::move(p));
  }
  return ctx;
}

void Context::applyLights(const std::vector<Vec3d>& intensity) {
  const std::vector<Light*> lights = in_.scene.lights.all();
  if (intensity.size() != in_.freeLights.size()) return;  // nothing solved (every scale given)
  for (size_t i = 0; i < in_.freeLights.size(); ++i)
    lights[in_.freeLights[i]]->setScale(intensity[i].cast<float>());
}

void Context::applyPoses(std::vector<PoseFit> fits) {
  for (const PoseFit& f : fits) applyObjectPose(in_.scene.mesh, f.object, f.pose, in_.scene.up);
  poses = std::move(fits);
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
  for (const Light* l : scene.lights.all()) {
    result.lightNames.push_back(l->label());
    result.lightRadiance.push_back(l->scale().value_or(Vec3f::Zero()).cast<double>());
  }
  result.exposure = exposure;
  result.peakMemoryMiB = peakMemoryMiB();
}

std::vector<int> fitViews(const PartWork& part, bool all) {
  std::vector<int> views = {part.view};
  if (!all) return views;
  double best = 0;
  for (const ViewSeen& s : part.seen)
    if (s.view == part.view) best = s.score;
  for (const ViewSeen& s : part.seen)
    if (s.view != part.view && s.pixels >= kMinFitPixels && s.score >= 0.5 * best)
      views.push_back(s.view);
  return views;
}

cv::Mat partPhoto(const cv::Mat& photo, const ViewWork& view, int part) {
  cv::Mat out;
  cv::warpAffine(photo, out, cv::Mat(view.warp.at(part)), photo.size(), cv::INTER_LINEAR,
                 cv::BORDER_REFLECT);
  return out;
}

}  // namespace ps::pipeline

// Reading a stage's inputs as declared (Reads, stage.hpp): every accessor names the scene.json
// keys and options it stands for and refuses them when the stage did not declare them.
#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "photoscene/core/error.hpp"
#include "runner.hpp"
#include "stage.hpp"

namespace ps::pipeline {

const std::vector<std::string>& optionNames() {
  static const std::vector<std::string> names = {
      "preset",   "texture_size", "work_width", "mean_albedo",  "render_spp", "eval_spp", "max_fit_iterations",
      "baseline", "write_gltf",   "library",    "ground_truth", "selection",  "fit_views", "denoise",
      "incident"};
  return names;
}

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
  return ctx_.in_.scene.lights.emittingParts();
}

std::vector<int> Reads::windowParts() const {
  need("lights.environment.window_parts");
  need("geometry");
  return ctx_.in_.scene.lights.openingParts();
}

const std::vector<int>& Reads::freeLights() const {
  need("lights.area");
  need("lights.environment");
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

float Reads::photoClip(int view, double exposure) const {
  need("views[].image", view);
  return ctx_.in_.views.at(view).clips && exposure > 0
             ? static_cast<float>(1.0 / exposure)
             : std::numeric_limits<float>::infinity();
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

const std::optional<std::string>& Reads::partCategory(int part) const {
  static const std::optional<std::string> none;
  need("parts.{}.category", -1, part);
  const io::PartDesc* d = partDesc(ctx_.in_.scene, ctx_.parts.at(part).name);
  return d ? d->category : none;
}

bool Reads::categoryInsisted(int part) const {
  return partCategory(part).has_value() && synthesisOptions().textureRequired;
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

bool Reads::refinePoses() const {
  need("options.refine_poses");
  return ctx_.in_.scene.desc.options.refinePoses;
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
  return presetUnless("render_spp", ctx_.in_.options.renderSpp, ctx_.in_.budget.renderSpp);
}

int Reads::evalSpp() const {
  return presetUnless("eval_spp", ctx_.in_.options.evalSpp, ctx_.in_.budget.evalSpp);
}

int Reads::incidentSamples() const {
  return presetUnless("incident", ctx_.in_.options.incidentSamples,
                      ctx_.in_.budget.incidentSamples);
}

int Reads::incidentDirectSamples(int round) const {
  const PresetBudget& b = ctx_.in_.budget;
  return presetUnless("incident", ctx_.in_.options.incidentDirectSamples,
                      round == 0 ? b.incidentDirectSamples : b.incident1DirectSamples);
}

const PartFitOptions& Reads::fitOptions() const {
  needOption("preset");
  return ctx_.in_.fitOptions;
}

SynthesisOptions Reads::synthesisOptions() const {
  return presetUnless("selection", ctx_.in_.options.selection, ctx_.in_.budget.synthesis);
}

bool Reads::denoise() const {
  needOption("denoise");
  return ctx_.in_.options.denoise;
}

bool Reads::fitAllViews() const {
  needOption("fit_views");
  return ctx_.in_.options.fitAllViews;
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

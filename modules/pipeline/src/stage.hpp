// A stage of the pipeline: what it reads, what it writes, and how it computes one unit (private
// to the module; README "Adding a stage").
//
// A stage declares its inputs: scene.json keys, run options, files of the output folder, and the
// upstream stages whose results it reads. The runner (runner.hpp) derives every cache key from
// these declarations alone, so a key cannot drift from what the stage reads: the stage reaches
// its inputs only through `Reads`, which refuses (ps::Exception) any input the stage did not
// declare. Upstream results live in the Context's work state (ViewWork, PartWork), written by the
// stage named beside each field.
//
// Declared scene.json keys are dot paths into the file as written: `lights`, `views[].camera`,
// `parts.{}.fixed`. `[]` is every element of an array and `{}` every member of an object, except
// that a per-view stage sees only its own `views[]` element and a per-part stage only its own
// `parts.{}` member. A key whose value names a file (`geometry`, `views[].image`,
// `views[].segments`, `lights.environment.image`) stands for the bytes of that file, not its
// path, so moving a file leaves the keys as they were and editing it does not.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "context.hpp"

namespace ps::pipeline {

/// What one unit of a stage is.
enum class Unit {
  Global,  ///< one unit for the run
  View,    ///< one unit per input view (0, 1, ...)
  Part,    ///< one unit per material part (in the OBJ's order)
};

/// What a stage reads and writes. Nothing else goes into its cache key.
struct StageDecl {
  std::string name;    ///< cache entries `<name>` / `<name>-<view>` / `<name>-<part>`
  std::string record;  ///< row of the stage table (empty: `name`); rows add up
  Unit unit = Unit::Global;
  uint64_t version = 1;              ///< bump when the stage's algorithm changes
  std::vector<std::string> scene;    ///< scene.json keys ("" is the whole file)
  std::vector<std::string> options;  ///< run options (see `optionNames()`)
  std::vector<std::string> outputs;  ///< files of the output folder it reads (by bytes)
  std::vector<std::string> after;    ///< upstream stages whose results it reads
  std::vector<std::string> writes;   ///< what it produces (work-state fields, output files)
  bool cached = true;     ///< false: a cheap derived step, computed every run, not a table row
  bool parallel = false;  ///< units computed in parallel (each must only touch its own unit)
  const std::string& row() const { return record.empty() ? name : record; }
};

/// The run options a stage may declare, each with what it stands for.
///   preset            the resolved preset (--preset, else scene.json options.preset): budgets
///   texture_size      --texture-size
///   work_width        the analysis resolution
///   mean_albedo       the scale pin
///   render_spp        PipelineOptions::renderSpp (when set)
///   max_fit_iterations
///   selection         PipelineOptions::selection (when set)
///   baseline          --baseline
///   write_gltf        PipelineOptions::writeGltf
///   library           the graph library's content (and the exemplar bank's format)
///   ground_truth      the case folder's ground-truth renders, cameras and lights (eval)
///   fit_views         PipelineOptions::fitAllViews
///   incident          PipelineOptions::incidentSamples, incidentDirectSamples (when set)
const std::vector<std::string>& optionNames();

/// The inputs of one stage unit, as declared: each accessor throws ps::Exception naming the
/// stage and the missing declaration when the stage did not declare what it reads.
class Reads {
 public:
  Reads(const Context& ctx, const StageDecl& decl, int unit);

  // scene.json
  /// mesh (as the `poses` stage moved it), parts, area lights: `geometry`, `up`, `lights.area`,
  /// `lights.auto_ceiling_spacing`
  const Scene& sceneGeometry() const;
  const Scene& litScene() const;          ///< the whole scene for the path tracer: + `lights`
  std::vector<int> emitterParts() const;  ///< parts that emit: `lights.area[].part`, `geometry`
  std::vector<int> windowParts() const;   ///< `lights.environment.window_parts`, `geometry`
  const std::vector<int>& freeLights() const;  ///< indices in lights.all() whose scale is fitted:
                                               ///< `lights.area`, `lights.environment`
  const Camera& camera(int view) const;        ///< working resolution: `views[].camera`, work_width
  const cv::Mat& photo(int view)
      const;  ///< CV_32FC3: `views[].image`, `views[].color_space`, `views[].camera`, work_width
  /// The level at which the view's photo, divided by `exposure`, is clipped: 1 / exposure for an
  /// integer-coded photo, infinity for a float one (`views[].image`)
  float photoClip(int view, double exposure) const;
  const cv::Mat& labels(int view) const;  ///< CV_32SC1 or empty: `views[].segments` + the photo's
  const std::map<int, int>& segmentParts(int view) const;               ///< `views[].segment_parts`
  const std::optional<std::string>& partGraph(int part) const;          ///< `parts.{}.graph`
  const std::optional<std::string>& partCategory(int part) const;       ///< `parts.{}.category`
  /// The part's category is given and the selection options insist on a texture of it
  /// (SynthesisOptions::textureRequired): `parts.{}.category`, preset, selection
  bool categoryInsisted(int part) const;
  const std::optional<io::HomogeneousDesc>& partFixed(int part) const;  ///< `parts.{}.fixed`
  bool partSkip(int part) const;                                        ///< `parts.{}.skip`
  uint64_t seed() const;                                                ///< `options.seed`
  bool refinePoses() const;                                             ///< `options.refine_poses`
  const fs::path& sceneFile() const;                                    ///< "" (the whole file)
  const fs::path& evalScene() const;  ///< scene.json for `eval`: "" and ground_truth
  const Scene& wholeScene() const;    ///< "" (the whole file)
  int viewCount() const;  ///< free: the number of views is part of every key (the units)
  // run options
  const std::string& preset() const;
  const PresetBudget& budget() const;        ///< preset (its renderSpp: use renderSpp())
  int renderSpp() const;                     ///< preset, render_spp
  int evalSpp() const;                       ///< preset, eval_spp
  int incidentSamples() const;               ///< preset, incident: path samples per grid bin
  int incidentDirectSamples(int round) const;  ///< preset, incident: lamp samples per grid point
  const PartFitOptions& fitOptions() const;  ///< preset
  SynthesisOptions synthesisOptions() const;  ///< preset, selection
  std::optional<int> maxFitIterations() const;
  bool fitAllViews() const;  ///< fit_views
  bool denoise() const;      ///< denoise
  int textureSize() const;
  double meanAlbedo() const;
  Baseline baseline() const;
  bool writeGltf() const;
  const GraphLibrary& library() const;
  const std::string& bankName() const;  ///< library
  /// Where the exemplar bank is cached: no declaration (where a cache lives changes no result).
  const fs::path& bankCache() const;
  /// The output folder: no declaration for writing; reading a file of it needs `outputs`.
  const fs::path& out() const;
  fs::path outFile(const std::string& name) const;

  const StageDecl& decl() const { return decl_; }
  int unit() const { return unit_; }

 private:
  friend class Runner;
  void need(std::string_view sceneKey, int view = -1, int part = -1) const;
  void needOption(std::string_view option) const;
  /// `value` when the run option `option` sets it, else the preset's `budgeted` (both declared).
  template <class T>
  T presetUnless(std::string_view option, const std::optional<T>& value, const T& budgeted) const {
    needOption("preset");
    needOption(option);
    return value.value_or(budgeted);
  }
  const Context& ctx_;
  const StageDecl& decl_;
  int unit_;
};

/// One stage. Subclasses name it and its unit here and fill the rest of `decl` in their
/// constructor, and implement the unit's work.
class Stage {
 public:
  explicit Stage(std::string name, Unit unit = Unit::Global) {
    decl.name = std::move(name);
    decl.unit = unit;
  }
  virtual ~Stage() = default;
  StageDecl decl;
  /// Whether unit `u` runs in this run (e.g. only the parts being fitted); a unit that does not
  /// run keeps its key (downstream keys include it) but computes and loads nothing.
  virtual bool applies(const Context& ctx, int u) const {
    (void)ctx;
    (void)u;
    return true;
  }
  /// Computes unit `u` into the work state. Returns false when there is no result to keep (the
  /// run was stopped, or nothing needed solving): nothing is stored and nothing counted.
  virtual bool compute(Context& ctx, const Reads& in, int u) = 0;
  /// The unit's result, for the cache (what `compute` wrote; `load` reads it back).
  virtual void save(const Context& ctx, int u, Archive& a) const = 0;
  /// Reads a cache entry back; false: unusable (e.g. the files it stands for are gone).
  virtual bool load(Context& ctx, const Reads& in, int u, Archive& a) = 0;
  /// After every unit, loaded or computed: cheap state derived from the units' results.
  virtual void finish(Context& ctx, const Reads& in) {
    (void)ctx;
    (void)in;
  }
};

/// A cheap step derived again on every run (`decl.cached` false, no row of the stage table):
/// nothing to save or load.
class DerivedStage : public Stage {
 public:
  explicit DerivedStage(std::string name, Unit unit = Unit::Global) : Stage(std::move(name), unit) {
    decl.cached = false;
  }
  void save(const Context&, int, Archive&) const final {}
  bool load(Context&, const Reads&, int, Archive&) final { return false; }
};

using StageList = std::vector<std::unique_ptr<Stage>>;

}  // namespace ps::pipeline

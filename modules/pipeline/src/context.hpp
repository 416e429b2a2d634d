// The state the pipeline's stages pass along (private to the module).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/align/pose.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/graph.hpp"
#include "photoscene/optim.hpp"
#include "photoscene/pipeline/pipeline.hpp"
#include "photoscene/pipeline/stage_cache.hpp"
#include "photoscene/select/synthesis.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/render.hpp"
#include "photoscene/scene.hpp"
#include "photoscene/select/exemplar_bank.hpp"

namespace ps::pipeline {

/// Per-preset budgets of the stages other than the part fit (PartFitOptions::preset has those).
struct PresetBudget {
  int lightSpp = 32;        ///< one-light-at-a-time renders
  int incidentSamples = 4;  ///< samples per incident-light bin
  int incidentStride = 8;
  /// light samples per light at every point of round 0's incident-light grids (incident0:
  /// select, fit, refine0; IncidentLightOptions::directSamples). 0: the lamps are found by the
  /// bins' path samples alone, and the grid's shading varies by tens of percent from point to
  /// point. Selection has come to rely on that noise: with the lamps sampled the flat material's
  /// render loses the blotches that matched some of the photo's texture energy, textured finalists
  /// win more parts and the pixel error rises (yardstick check half, 1cc2d00: masked RMSE 16.41 ->
  /// 17.45, 8 of 56 parts change graph, a cracked concrete floor to a glossy parquet checker at
  /// RMSE 44). Off in round 0 until selection stops favouring texture (issue 17).
  int incidentDirectSamples = 0;
  /// ... and of round 1's (incident1: refine1 and the bounce stage, which set every final albedo
  /// and roughness, not the graphs). With the lamps sampled the grids' shading is right to a few
  /// percent where path samples alone leave 5-7 % per part (three synthetic views, exact
  /// geometry, balanced: the sofa 5.9 % off; with them every part within 2.6 %, MultiView.*).
  int incident1DirectSamples = 32;
  int renderSpp = 16;  ///< final renders (denoised by default: 16 spp denoised beats 64 raw)
  /// the evaluation's novel and relit renders: what their noise floor needs once denoised (the
  /// twin's own error against the ground truth is several times the noise left at 8 spp)
  int evalSpp = 8;
  int refineCandidates = 7;  ///< roughness values tried in the second round
  SynthesisOptions synthesis;  ///< selection by synthesis (the vote's finalists fitted briefly)
  static PresetBudget of(const std::string& preset);
};

/// The inputs of a run at the working resolution (read through `Reads`, stage.hpp).
struct ViewInput {
  Camera camera;   ///< at the working resolution
  cv::Mat photo;   ///< CV_32FC3, working resolution
  cv::Mat labels;  ///< CV_32SC1 regions at the working resolution (empty: proposed)
  /// an integer-coded photo (PNG, JPEG) clips at 1; a float one (EXR, HDR) does not
  bool clips = true;
};

/// What the stages compute per view (each field written by the stage named).
struct ViewWork {
  GBuffer gbuffer;                   ///< geometry
  std::map<int, cv::Mat> photoMask;  ///< align: part -> M_photo (photo frame)
  std::map<int, cv::Matx23d> warp;   ///< align: part -> Eq. (1), photo -> render pixels
  std::map<int, cv::Mat> fitMask;    ///< align: part -> M_aln in the render frame
  cv::Mat lightMask;       ///< align: pixels where geometry and photo agree (render frame)
  IncidentLightGrid grid;  ///< incident0, then incident1
};

/// `photo` warped into the render frame for a part (the align stage's warp of that part).
cv::Mat partPhoto(const cv::Mat& photo, const ViewWork& view, int part);

/// How one view sees one part (observe), as the materials file's `fit.views` records it.
struct ViewSeen {
  int view = 0;
  int pixels = 0;         ///< M_aln pixels
  double meanCosine = 0;  ///< mean |cos| between the surface normal and the view direction
  double agreement = 1;   ///< appearance agreement with the other views (align::chooseView)
  double score = 0;       ///< pixels x mean cos x agreement: the largest is the part's view
  /// of the points of the part's M_aln in its other views that this view sees on the part, the
  /// share in this view's M_aln (align::maskConsistency, pooled over the other views): how much
  /// of the part its photo region covers; -1: none seen
  double maskConsistency = -1;
};

enum class PartMode { Fit, Homogeneous, Fixed, Skip, Emitter, Window, Unseen };

struct PartWork;
/// The views a part may be fitted in: its chosen view; with `all` (PipelineOptions::fitAllViews),
/// also every other view whose chooseView score is at least half the chosen view's (the fit
/// pools them for a homogeneous part; the incident grids cover them all). The chosen view first.
std::vector<int> fitViews(const PartWork& part, bool all);
constexpr int kMinFitPixels = 16;  ///< fewer M_aln pixels: a part is fitted in closed form
const char* partModeName(PartMode m);

/// What the stages compute per part (each field written by the stage named).
struct PartWork {
  // parts: what the part gets
  int id = -1;
  std::string name;
  PartMode mode = PartMode::Fit;
  std::string skipped;  ///< why it was not fitted (materials file fit.skipped)
  // observe (and parts: the fixed material)
  int view = -1;                         ///< the view it is fitted in
  int pixels = 0;                        ///< M_aln pixels in that view
  Vec3f median = Vec3f::Constant(0.5f);  ///< median photo colour over M_aln / exposure (linear)
  std::vector<ViewSeen> seen;            ///< every view that sees the part
  // select
  std::string graph = "homogeneous", category = "homogeneous";
  std::vector<std::string> runnersUp;
  std::vector<GraphVote> candidates;  ///< the kNN vote's top 5 (weight: share of the vote)
  struct Finalist {
    std::string graph, category;
    double vote = 0, loss = 0, seconds = 0;
    double fitLoss = 0;  ///< the short fits' loss on their own pixels (loss: on held-back ones)
    double pixelRmse = 0, contrast = 0;  ///< its render's masked RMSE and typical local contrast
    double coarseContrast = 0;  ///< the typical local contrast at the coarse scale (synthesis)
    double chroma = 0;          ///< its render's chromaticity spread (synthesis)
    double chromaOutside = 0;   ///< its render's share outside the photo's colours
    bool qualifies = true;  ///< passed the pixel-error, contrast and colour tests
  };
  std::vector<Finalist> finalists;  ///< selection by synthesis: the short fits, lowest loss first
  double photoContrast = 0;  ///< the photo's typical local contrast over the part (synthesis)
  double photoCoarseContrast = 0;  ///< the same at the coarse scale
  double photoChroma = 0;          ///< the photo's chromaticity spread over the part
  bool heldOut = false;  ///< the finalists were scored on held-back pixels (synthesis)
  /// the graph whose full fit was rejected for more structure than the photo shows (fit), else
  /// empty
  std::string textureRejected;
  /// where the fit starts: the synthesis winner's short fit (values in MaterialGraph::values()
  /// layout, UV); empty values: the graph's defaults and the identity UV
  std::vector<float> startValues;
  UvParams startUv;
  // fit
  std::vector<float> values;
  UvParams uv;
  float roughness = 0.7f;                ///< the held mean roughness (or homogeneous roughness)
  float roughnessScale = 1.0f;           ///< multiplies the graph's roughness map to `roughness`
  Vec3f albedo = Vec3f::Constant(0.5f);  ///< homogeneous albedo
  float metallic = 0.0f, specular = 0.5f;
  double loss = 0, seconds = 0;
  int iterations = 0;
  std::vector<double> history;
  // refine0, refine1
  float albedoScale = 1.0f;
  Vec3f albedoOffset = Vec3f::Zero();  ///< added to the albedo map before the scale
  float roughnessFactor = 1.0f;
  double refineLoss = 0;
  // incident1: the mean albedo of the material its grids were traced with (refine0's)
  Vec3f gridAlbedo = Vec3f::Zero();
  // bounce: the factor on the mean albedo for the light the new albedos bounce (1: none)
  Vec3f bounceFactor = Vec3f::Ones();
  bool textured() const { return mode == PartMode::Fit; }
};

class Reads;

/// Everything a run reads (private: stages reach it through `Reads`, stage.hpp).
struct RunInputs {
  PipelineOptions options;
  std::string preset;
  PresetBudget budget;
  PartFitOptions fitOptions;
  uint64_t seed = 0;
  Scene scene;  ///< area light radiances as the last lights stage left them
  std::unique_ptr<GraphLibrary> library;
  std::string bankName;          ///< the exemplar bank's file name (format, library hash, options)
  std::vector<ViewInput> views;  ///< at the working resolution
  std::vector<int>
      freeLights;  ///< indices in scene.lights.all() of the lights whose scale is fitted
};

/// The state the stages pass along: the inputs (private) and the work state.
class Context {
 public:
  std::vector<ViewWork> views;
  std::vector<PartWork> parts;
  float albedoPin = 1.0f;  ///< observe: scale from photo medians to neutral albedos
  /// Per view: observe's estimate from the photos alone, then the solves of lights0 and lights1.
  /// The fit and refine stages compare their renders with photo / exposure[view].
  std::vector<double> exposure;
  double viewExposure(int view) const {
    return view >= 0 && view < static_cast<int>(exposure.size()) && exposure[view] > 0
               ? exposure[view]
               : 1.0;
  }
  /// poses: the objects moved onto the labels, in the order they were moved (applyPoses)
  std::vector<PoseFit> poses;
  std::unique_ptr<StageCache> cache;
  PipelineResult result;
  Timer clock;  ///< since the run started

  /// Reads scene.json and everything it names, checks them and resolves the options; bad input
  /// throws ps::InputError before anything is written.
  static std::unique_ptr<Context> load(const PipelineOptions& options);
  /// The lights stages' result: the free lights' scales (in `freeLights` order) written into the
  /// scene the later path tracers see.
  void applyLights(const std::vector<Vec3d>& intensity);
  /// The poses stage's result: `poses` kept and its objects moved in the scene's mesh, which every
  /// later stage and the twin's geometry use.
  void applyPoses(std::vector<PoseFit> fits);
  /// The run in one line (scene, views, parts, lights, preset) for the log.
  std::string describe() const;
  /// Fills `result` with what the run recovered (lights, exposure, time, memory).
  void finishResult();

 private:
  friend class Reads;   // the stages' only way to their inputs
  friend class Runner;  // keys from the declarations
  friend struct ContextTesting;
  RunInputs in_;
};

/// Tests only: the inputs, to perturb them and compare keys.
struct ContextTesting {
  static RunInputs& inputs(Context& ctx) { return ctx.in_; }
};

/// Materials for rendering: neutral (photo medians; reads the stages parts and observe, and
/// `parts.{}.fixed`), or fitted (+ select, fit, refine0; maps at `mapSize`; `library`).
std::vector<PartMaterial> neutralMaterials(const Context& ctx, const Reads& in);
std::vector<PartMaterial> fittedMaterials(const Context& ctx, const Reads& in, int mapSize);
/// A fitted part's albedo averaged over its material as fittedMaterials renders it
/// (homogeneous: its albedo; textured: clamp(albedoScale (map + albedoOffset), 0, 1) averaged
/// over the map at the fit's map size). `mapMean` (optional, textured): the map's own mean.
Vec3f meanAlbedo(const Context& ctx, const Reads& in, const PartWork& part,
                 Vec3f* mapMean = nullptr);

/// A homogeneous part's closed-form fit (optim's fitHomogeneous) over the views fitViews names
/// (`fit_views`): `geometry` and `photo` are its chosen view's (photo divided by that view's
/// exposure); each further view adds its M_aln, grid and photo / exposure. Reads the stages
/// align, observe and the current incident grids, and the views' photos and cameras.
HomogeneousFit fitHomogeneousPart(const Context& ctx, const Reads& in, const PartWork& part,
                                  const PartGeometry& geometry, const cv::Mat& photo,
                                  int candidates);

/// Stage bookkeeping: time and units computed / loaded.
class StageScope {
 public:
  StageScope(Context& ctx, std::string name);
  ~StageScope();
  void computed(int n = 1) { rec_.computed += n; }
  void cached(int n = 1) { rec_.cached += n; }

 private:
  Context& ctx_;
  StageRecord rec_;
  Timer timer_;
  /// std::uncaught_exceptions() at the start: more at the end means the stage stopped
  int exceptions_;
};

}  // namespace ps::pipeline

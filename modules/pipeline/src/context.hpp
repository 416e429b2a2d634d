// The state the pipeline's stages pass along (private to the module).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/core/timer.hpp"
#include "photoscene/graph.hpp"
#include "photoscene/optim.hpp"
#include "photoscene/pipeline/pipeline.hpp"
#include "photoscene/pipeline/stage_cache.hpp"
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
  int renderSpp = 64;       ///< final renders
  int refineCandidates = 7; ///< roughness values tried in the second round
  static PresetBudget of(const std::string& preset);
};

struct ViewWork {
  Camera camera;        ///< at the working resolution
  cv::Mat photo;        ///< CV_32FC3, working resolution
  cv::Mat labels;       ///< CV_32SC1 regions at the working resolution (empty: proposed)
  uint64_t photoKey = 0;
  GBuffer gbuffer;
  uint64_t geometryKey = 0;
  // align
  uint64_t alignKey = 0;
  std::map<int, cv::Mat> photoMask;     ///< part -> M_photo (photo frame)
  std::map<int, cv::Matx23d> warp;      ///< part -> Eq. (1), photo -> render pixels
  std::map<int, cv::Mat> fitMask;       ///< part -> M_aln in the render frame
  cv::Mat lightMask;                    ///< pixels where geometry and photo agree (render frame)
  // lighting
  IncidentLightGrid grid;
  uint64_t incidentKey = 0;
  cv::Mat partPhoto(int part) const;    ///< the photo warped into the render frame for a part
};

enum class PartMode { Fit, Homogeneous, Fixed, Skip, Emitter, Window, Unseen };
const char* partModeName(PartMode m);

struct PartWork {
  int id = -1;
  std::string name;
  PartMode mode = PartMode::Fit;
  std::string skipped;                  ///< why it was not fitted (materials file fit.skipped)
  int view = -1;                        ///< the view it is fitted in
  int pixels = 0;                       ///< M_aln pixels in that view
  Vec3f median = Vec3f::Constant(0.5f); ///< median photo colour over M_aln (linear)
  std::string graph = "homogeneous", category = "homogeneous";
  std::vector<std::string> runnersUp;
  std::vector<GraphVote> candidates;    ///< the kNN vote's top 5 (weight: share of the vote)
  // the fit
  std::vector<float> values;
  UvParams uv;
  float roughness = 0.7f;               ///< the held mean roughness (or homogeneous roughness)
  float roughnessScale = 1.0f;          ///< multiplies the graph's roughness map to `roughness`
  Vec3f albedo = Vec3f::Constant(0.5f); ///< homogeneous albedo
  float metallic = 0.0f, specular = 0.5f;
  double loss = 0, seconds = 0;
  int iterations = 0;
  std::vector<double> history;
  // second round
  float albedoScale = 1.0f;
  Vec3f albedoOffset = Vec3f::Zero();  ///< added to the albedo map before the scale
  float roughnessFactor = 1.0f;
  double refineLoss = 0;
  uint64_t selectKey = 0, fitKey = 0, refineKey = 0;
  bool textured() const { return mode == PartMode::Fit; }
};

struct Context {
  PipelineOptions options;
  std::string preset;
  PresetBudget budget;
  PartFitOptions fitOptions;
  uint64_t seed = 0;
  Scene scene;
  std::unique_ptr<GraphLibrary> library;
  std::vector<ViewWork> views;
  std::vector<PartWork> parts;
  std::unique_ptr<StageCache> cache;
  PipelineResult result;
  float albedoPin = 1.0f;               ///< scale from photo medians to neutral albedos
  std::vector<int> freeLights;          ///< area-light indices whose radiance is fitted
  uint64_t lights0Key = 0, lights1Key = 0, exportKey = 0;
  std::vector<double> exposure;

  /// Materials for rendering: neutral (photo medians), or fitted (maps at `mapSize`).
  std::vector<PartMaterial> neutralMaterials() const;
  std::vector<PartMaterial> fittedMaterials(int mapSize, bool withRefine) const;
};

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

// stages (pipeline.cpp)
void stageGeometry(Context& ctx);
void stageAlign(Context& ctx);
void stageLights(Context& ctx, bool fitted);
void stageIncident(Context& ctx, bool fitted);
void stageSelect(Context& ctx);
void stageFit(Context& ctx);
void stageBaseline(Context& ctx);
void stageRefine(Context& ctx, int round);  ///< 0: before the global light solve, 1: after
// outputs (outputs.cpp)
void stageExport(Context& ctx);
void stageMetrics(Context& ctx, double secondsSoFar);
void stageReport(Context& ctx);

}  // namespace ps::pipeline

// The whole method as one call: photos + coarse CAD in (scene.json), a digital twin out (the
// output folder of ../shared/spec/scene-format.md section 3).
//
// Stages (paper sections 3.1-3.4; each cached on disk under OUT/.cache, keyed by a hash of what
// it declares it reads: scene.json keys, file bytes, options and upstream results, so a rerun
// redoes only what changed; the module's README, "Adding a stage", says how a stage declares):
//   geometry   per view: G-buffers of the coarse geometry at the working resolution
//   align      per view: photo regions matched to parts, the Eq. (1) box warp, aligned masks
//   lights0    emitter intensities under neutral materials (per-part photo medians, roughness
//              0.7), non-negative least squares over the pixels where geometry and photo agree
//   incident0  per view: incident-light grids under the neutral materials and lights0
//   select     per part: the material graph (kNN over the exemplar bank, or the user's choice;
//              homogeneous below the small-part threshold)
//   fit        per part, in parallel: graph parameters, mean roughness, UV transform
//   lights1    the global solve over all views with the fitted materials (per-view exposure)
//   incident1  per view: incident-light grids under the fitted materials and lights1
//   refine     per part: the second round, albedo scale and roughness only
//   export     textures at --texture-size (graphs re-evaluated there), materials/*.json,
//              lights.json, scene.json, renders, glTF, metrics.json, report.html
//
// The global scale that one image cannot fix (brighter lights and darker materials explain the
// photo equally well) is pinned by the neutral materials: their albedos are the parts' photo
// medians scaled so that the pixel-weighted mean albedo luminance is `meanAlbedo` (0.5), and
// every later stage inherits that scale.
//
//   ps::PipelineOptions o;
//   o.scene = "room/scene.json";  o.out = "room-twin";
//   ps::PipelineResult r = ps::runPipeline(o);
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "photoscene/select/synthesis.hpp"
#include "photoscene/core/math.hpp"

namespace ps {

enum class Baseline {
  None,           ///< the method
  PixelMedian,    ///< per part the median photo colour as albedo, roughness 0.7, flat (IM2CAD)
  ShadingMedian,  ///< per part the median of photo / rendered diffuse shading (inverse rendering stand-in)
};
Baseline parseBaseline(const std::string& name);  ///< "none" | "pixel-median" | "shading-median"
const char* baselineName(Baseline b);

struct PipelineOptions {
  std::filesystem::path scene;               ///< scene.json
  std::filesystem::path out;                 ///< output folder (created; existing outputs replaced)
  std::optional<std::string> preset;         ///< overrides scene.json's options.preset
  int textureSize = 1024;                    ///< exported maps, any size >= 4
  int threads = 0;                           ///< 0 = all cores
  Baseline baseline = Baseline::None;
  /// Exemplar-bank cache (shared between runs); empty: defaultBankCache().
  std::filesystem::path bankCache;
  bool useStageCache = true;                 ///< false: recompute every stage
  int workWidth = 320;                       ///< analysis resolution (photo scaled down to this width)
  double meanAlbedo = 0.5;                   ///< the scale pin (see above)
  std::optional<int> renderSpp;              ///< final renders; default by preset
  std::optional<int> evalSpp;                ///< metrics' novel / relit renders; default by preset
  std::optional<int> maxFitIterations;       ///< caps the per-part iterations (tests)
  /// The incident-light grids (both rounds): path samples per bin (>= 1) and light samples per
  /// light at each grid point (>= 0; 0 finds the lamps by path samples alone); default by preset
  /// (fast 4 / 0, balanced 8 / 0, paper 16 / 0 in round 0; round 1 samples the lamps with 32).
  std::optional<int> incidentSamples;
  std::optional<int> incidentDirectSamples;
  /// Selection by synthesis (select/synthesis.hpp): how many of the kNN vote's graphs are fitted
  /// briefly on the part, and how; default by preset.
  std::optional<SynthesisOptions> selection;
  /// A homogeneous part is fitted over every view that sees it well (chooseView's score at least
  /// half the best view's), the photos' pixels pooled, instead of in its chosen view alone (issue
  /// 19, beyond the paper). Off by default: measured in pipeline/README.md.
  bool fitAllViews = false;
  /// The renders people look at and the evaluation scores (OUT/renders, metrics' novel and relit
  /// views) are denoised (ps::denoise, guided by each render's own albedo, normal, depth and
  /// variance) at the preset's render_spp. Never what the light solve or the fit read.
  bool denoise = true;
  bool writeReport = true;
  bool writeGltf = true;
};

struct StageRecord {
  std::string name;
  double seconds = 0;
  int computed = 0;  ///< units (views, parts, ...) computed in this run
  int cached = 0;    ///< units loaded from the stage cache
  double peakMemoryMiB = 0;  ///< the process's peak resident memory at the stage's end (ru_maxrss)
};

struct PipelineResult {
  std::filesystem::path out;
  std::string preset;
  std::vector<StageRecord> stages;
  double totalSeconds = 0;
  std::vector<std::string> lightNames;    ///< emitters (and "environment" last when present)
  std::vector<Vec3d> lightRadiance;       ///< recovered (or given) radiance, same order
  std::vector<double> exposure;           ///< per view
  double peakMemoryMiB = 0;               ///< the process's peak resident memory over the run
  const StageRecord* stage(const std::string& name) const;
  int computedUnits() const;              ///< sum over stages
};

/// Runs every stage. Bad input (scene.json and what it names, unknown graphs in `parts`, inputs
/// over the resource limits) throws ps::InputError before anything is written. SIGINT / SIGTERM
/// stop at the next check point with ps::Interrupted, leaving only whole files; a rerun continues
/// from the stage cache.
///
/// Testing hooks (environment variables, for the failure-safety tests; README "Robustness"):
///   PS_FAIL_AT_STAGE=<stage>   that stage throws ps::Exception as it starts
///   PS_PAUSE_AT_STAGE=<stage>  that stage waits (up to 60 s) for SIGINT / SIGTERM as it starts,
///                              first writing the file $PS_PAUSE_MARKER when that is set
PipelineResult runPipeline(const PipelineOptions& options);

namespace io { struct SceneDesc; }
class GraphLibrary;
/// What `parts` asks of the library, checked as runPipeline checks it before anything is written:
/// every `parts.<name>.graph` is a graph of `library`, every `parts.<name>.category` a category
/// with graphs in it and, with a graph given too, that graph's category. Throws ps::InputError
/// naming scene.file and the key.
void checkPartSettings(const io::SceneDesc& scene, const GraphLibrary& library);

/// The selection-by-synthesis settings a preset uses when PipelineOptions::selection is unset
/// (fast 2 / 2 / 8, balanced 3 / 3 / 12, paper 5 / 4 / 30: shortlist / categories / steps).
SynthesisOptions synthesisPreset(const std::string& preset);

/// Where runs share the exemplar-bank cache unless PipelineOptions::bankCache says otherwise:
/// $PS_CACHE_DIR, else $XDG_CACHE_HOME/photoscene, else ~/.cache/photoscene (else a folder in
/// the system's temporary directory).
std::filesystem::path defaultBankCache();

}  // namespace ps

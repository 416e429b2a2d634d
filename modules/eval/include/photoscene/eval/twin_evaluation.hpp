// Scoring a twin output folder (../shared/spec/scene-format.md section 3) against its case:
// the photos of the input views, per part over the aligned masks, and whatever ground-truth
// renders the case folder holds (novel views, relit views). Writes OUT/metrics.json.
//
//   ps::eval::EvalOptions opt;  opt.spp = 64;
//   ps::eval::TwinEvaluation e = ps::eval::evaluateTwin("OUT", "room/scene.json", opt);
//   ps::eval::writeMetricsJson("OUT", e, {{"geometry", 1.2}, {"select", 30.5}}, "balanced");
//
// What is compared (every number in both color spaces of metrics.hpp: srgb255 and linear):
//   views   input view i: the twin's render times exposure[i] (OUT/lights.json) against photo i,
//           whole image (RMSE, PSNR, SSIM, GMSD). The render is OUT/renders/view<i>.exr when
//           present and of the photo's size (written WITH the exposure applied, as `photoscene
//           render OUT` writes input views), else the twin path-traced here at options.spp times
//           exposure[i].
//   parts   the paper's per-part error: RMSE over the part's aligned mask M_aln (photo frame).
//           The G-buffer of the twin's geometry gives M_geo; the view's label image (regions
//           matched to parts with align::matchRegions, segment_parts pinned) or, without one,
//           align::proposeRegions gives M_photo; align::alignPart gives M_aln and warps the render
//           into the photo frame with Eq. (1); RMSE(warped render * exposure, photo) over M_aln.
//           Each part is scored in the view where its M_aln has the most pixels. Window parts and
//           emitter parts are left out (no material).
//   novel   every gt/novel<k>.{exr,hdr,png} of the case folder (the folder of SCENE.json) with
//           cameras/novel<k>.json: the twin rendered from that camera (resized to the reference
//           image's size when the sizes differ), times the input views' exposure (geometric mean).
//   relit   every gt/relit<k>.{exr,hdr,png} with a lights file in our lights.json form, the first
//           of lights_relit<k>.json, lights_relit.json, gt/twin/lights_relit<k>.json,
//           gt/twin/lights_relit.json that parses (the bundled sample and blender-room layouts);
//           camera cameras/relit<k>.json, else input view 0; times exposure[0] (view 0) or the
//           geometric mean. The twin is relit RELATIVELY when the case gives the lights of the
//           photo (gt/twin/lights.json, else lights_gt.json, in lights.json form): each twin
//           emitter's radiance is multiplied per channel by relit / original of its emitter
//           (matched by part, then name, then nearest rectangle center within 0.5 m; an emitter
//           with no match gets the mean ratio), and the environment likewise. This keeps the
//           twin's own albedo-intensity scale, which a photo cannot fix. Without the photo's
//           lights, the relit emitters replace the twin's (ps::makeLights, by name or part).
//
// Missing pieces are not errors: a case without gt/ gives empty novel / relit lists; a ground
// truth file that cannot be used is skipped with a note (TwinEvaluation::notes).
#pragma once

#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "photoscene/eval/metrics.hpp"

namespace ps::eval {

struct EvalOptions {
  int spp = 64;                 ///< samples per pixel for every render made here
  uint64_t seed = 0;            ///< path tracer seed
  bool useSavedRenders = true;  ///< read OUT/renders/view<i>.exr instead of rendering when usable
  bool parts = true;            ///< per-part RMSE over M_aln
  bool groundTruth = true;      ///< novel and relit ground truth of the case folder
  bool denoise = true;          ///< renders made here are denoised (renderTwinView), as run's are
  bool IsValid(std::string* error) const;
};

/// One image compared in both color spaces.
struct ImageScore {
  ImageMetrics srgb255{ColorSpace::Srgb255};
  ImageMetrics linear{ColorSpace::Linear};
};

struct ViewScore {
  int view = 0;
  std::string image;  ///< the photo, as named in scene.json (relative to its folder)
  ImageScore score;
  std::string render;  ///< "renders/view<i>.exr", or "path tracer, <spp> spp"
};

struct PartScore {
  std::string part;
  int view = -1;   ///< the view it was scored in
  int pixels = 0;  ///< M_aln pixels in that view
  double rmseSrgb255 = 0, rmseLinear = 0;
};

/// A ground-truth render found in a case folder.
struct GroundTruthRender {
  std::string name;  ///< "novel0", "relit0", ...
  enum class Kind { Novel, Relit } kind = Kind::Novel;
  std::filesystem::path image;                  ///< the reference render (linear after reading)
  std::optional<std::filesystem::path> camera;  ///< camera object; absent: input view `view`
  int view = 0;  ///< input view whose camera is used without `camera`
  std::optional<std::filesystem::path> lights;       ///< Relit: the relit lights (lights.json form)
  std::optional<std::filesystem::path> photoLights;  ///< Relit: the lights of the photo, if given
};

struct GroundTruthScore {
  std::string name;
  ImageScore score;
};

struct TwinEvaluation {
  std::vector<ViewScore> views;
  std::vector<PartScore> parts;  ///< sorted by part name
  std::vector<GroundTruthScore> novel, relit;
  std::vector<std::string> notes;  ///< ground truth skipped and why, renders made here
  std::string preset;              ///< OUT/scene.json options.preset (may be empty)
  double seconds = 0;              ///< time evaluateTwin took
};

/// The ground-truth renders of a case folder (see the header comment for the layouts).
std::vector<GroundTruthRender> findGroundTruth(const std::filesystem::path& caseDir, int numViews,
                                               std::vector<std::string>* notes = nullptr);

/// Scores the twin in `outDir` against the photos of `scenePath` and the case's ground truth.
/// Throws ps::InputError when outDir is not a twin folder, scenePath is bad input, their views
/// disagree in number or size, or an emitter of the twin has no radiance.
TwinEvaluation evaluateTwin(const std::filesystem::path& outDir,
                            const std::filesystem::path& scenePath,
                            const EvalOptions& options = {});

/// Writes OUT/metrics.json atomically:
///   {"color_spaces": {"srgb255": "...", "linear": "..."},
///    "views": [{"view": 0, "image": "photos/view0.png",
///               "srgb255": {"rmse", "psnr", "ssim", "gmsd"}, "linear": {...}}],
///    "parts": {"floor": {"view": 0, "pixels": 1234, "srgb255": {"rmse"}, "linear": {"rmse"}}},
///    "novel": [{"name": "novel0", "srgb255": {...}, "linear": {...}}], "relit": [...],
///    "stages": {"geometry": 1.2, ...}, "total_seconds": 12.3, "preset": "balanced"}
/// A number that is not finite (PSNR of identical images, RMSE of no pixels) is written as null.
/// @param stageSeconds  seconds per pipeline stage; empty: keep the existing file's "stages" and
///                      "total_seconds" (as `photoscene eval` does)
/// @param preset        empty: keep the existing file's "preset", else evaluation.preset
/// @param totalSeconds  NaN: the sum of stageSeconds
/// Other top-level keys of an existing metrics.json are kept.
void writeMetricsJson(const std::filesystem::path& outDir, const TwinEvaluation& evaluation,
                      const std::map<std::string, double>& stageSeconds = {},
                      const std::string& preset = "",
                      double totalSeconds = std::numeric_limits<double>::quiet_NaN());

/// The one-line definitions written under "color_spaces".
std::string colorSpaceDefinition(ColorSpace space);

}  // namespace ps::eval

// The per-part material fit of the paper (section 3.4): a material graph's parameters, one mean
// roughness and the part's UV transform, fitted so that the render layer's image of the part
// matches the photo.
//
//   loss = statWeight * L_stat + textureWeight * L_tex + placementWeight * L_place
//   L_stat = sum_c |mu_c(photo) - mu_c(render)| / nu + |var_c(photo) - var_c(render)| / nu^2  (Eq.
//   6-8,
//            masked; nu = mean photo luminance over the mask, so the loss is unitless)
//   L_tex  = ps::textureLossForward (masked multi-scale texture statistics, the Eq. 9 stand-in;
//            optionally with the joint statistics of features/texture_ps.hpp, `ps*` below)
//   L_place = ps::placementLoss (features/texture_placement.hpp: 1 - the correlation of the
//            low-passed luminances of render and photo over the mask; Eq. 9's pixel term after the
//            warp: the caller's photo is the aligned one). On in "balanced" (0.1), off elsewhere.
//   + roughnessPriorWeight * L_prior + highlightWeight * L_hl + albedoCeilingWeight * L_ceil
//            (optim/roughness_prior.hpp: the category's log-roughness prior, the highlight
//            contrast where the incident light predicts one, a soft barrier on albedo near 1;
//            on in "balanced" and "fast", off in "paper")
//   + paletteWeight * L_palette (graph/palette_prior.hpp: a colour ramp's colours, or all the
//            graph's, keep the chroma differences of its defaults; off in every preset)
//
// The roughness output of the graph is replaced by one scalar while fitting (initialised to the
// mean of the graph's roughness map); the result says how to rescale the full map to it.
// Alternation (coarse to fine): every `uvSearchEvery` iterations a discrete search over UV
// rotation x log-scale x offset (forward passes only) picks the best transform with the current
// maps; in between, Adam moves the graph parameters (normalised to [0, 1] by their ranges), the
// roughness and the UV transform continuously. Early stopping on a moving-average plateau;
// random restarts (short probes from random parameters, the best continued) only when
// `restarts` > 0.
//
//   ps::PartGeometry geo = ps::preparePartGeometry(gb, camPos, grid, mask, part);
//   ps::TextureLossTarget target(photo, mask);
//   ps::PartFitResult r = ps::fitPart(lib.get("wood_planks"), geo, photo, target,
//                                     ps::PartFitOptions::preset("balanced"));
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/features/texture_loss.hpp"
#include "photoscene/features/texture_placement.hpp"
#include "photoscene/graph/material_graph.hpp"
#include "photoscene/graph/palette_prior.hpp"
#include "photoscene/optim/adam.hpp"
#include "photoscene/optim/roughness_prior.hpp"
#include "photoscene/optim/uv_spectrum.hpp"
#include "photoscene/render/render_layer.hpp"

namespace ps {

/// What `PartFitOptions::onProgress` sees: after each Adam step, and every 64 candidates of a
/// discrete UV search (a `paper` search is 57,600 candidates, minutes on one thread).
struct PartFitProgress {
  enum class Phase { Step, Search };
  Phase phase = Phase::Step;
  int iteration = 0;           ///< Adam steps taken so far (all starts and levels)
  int candidates = 0;          ///< UV candidates evaluated so far (all searches)
  int level = 0;               ///< image-pyramid level of the step (0: full resolution)
  double loss = 0;             ///< Step: the step's loss (at its level); Search: the state's before it
  /// Step: the best state of the current phase (what fitPart would return if stopped here);
  /// Search: the state the search started from
  std::vector<float> values;
  UvParams uv;
  float roughness = 0.5f;
};

struct PartFitOptions {
  int maxIterations = 300;
  int mapSize = 128;               ///< graph maps N x N (power of two)
  float learningRate = 0.02f;      ///< Adam, on parameters normalised to [0, 1]
  float uvLearningRate = 0.01f;    ///< Adam, on rotation (rad), log-scale and offsets
  float statWeight = 0.1f;         ///< a
  float textureWeight = 1.0f;      ///< b
  /// Weight of the placement term (0 = off): where the pattern lies (UV offset and rotation of
  /// planks, grout), which the texture statistics cannot see. "balanced": 0.1 (measured).
  float placementWeight = 0.0f;
  /// Its low-pass (pixels at full resolution; halved per coarse level, at least 0.5).
  float placementSigma = 2.0f;
  /// With the placement term on, after each UV search: this many offsets (a low-discrepancy set
  /// over [0, 1)^2 around the best, so every pattern period is sampled) at the best rotation and
  /// scale, compared at full resolution (0 = none: only Adam moves the offset).
  int placementOffsets = 16;
  /// The texture loss's joint statistics (TextureLossWeights::ps*). When any is > 0, the fit
  /// builds its own texture-loss targets (the caller's target options with these five weights, on
  /// the geometry's pixels); all 0 = the caller's target as it is.
  float psAutoLowpass = 0.0f, psAutoMagnitude = 0.0f, psCrossOrientation = 0.0f,
        psCrossScale = 0.0f, psColor = 0.0f;
  /// The texture loss's colour distribution (TextureLossWeights::colorSliced), the same way: > 0
  /// builds the fit's own targets with it.
  float colorSliced = 0.0f;
  /// The texture loss's spectral shape (TextureLossWeights::bandShape), the same way. "balanced"
  /// and "fast": 0.3 (measured, modules/optim/README.md).
  float bandShape = 0.0f;
  /// Weight of the roughness prior L_prior (0 = off; roughness free in [0.02, 1]). On, the fit
  /// also keeps the roughness in the prior's [min, max] and starts it there.
  float roughnessPriorWeight = 0.0f;
  /// The category whose prior is used ("" = the graph's own category).
  std::string roughnessCategory;
  /// Weight of the highlight term L_hl (0 = off): the highlight contrast of photo and render over
  /// the pixels where the incident light predicts a highlight (none predicted: the term is 0).
  float highlightWeight = 0.0f;
  HighlightOptions highlight;
  /// Weight of the albedo ceiling L_ceil (0 = off) and its knee: albedo texels above the knee are
  /// pushed down softly, so that a channel does not pin at 1.0.
  float albedoCeilingWeight = 0.0f;
  float albedoCeilingKnee = 0.9f;
  /// Weight of the palette prior L_palette (graph/palette_prior.hpp; 0 = off): a colour ramp's
  /// colours (or all the graph's, paletteScope) keep the chroma differences of the graph's
  /// defaults, so the fit can turn the colours' hue as a whole but not spend them on the photo's
  /// colour moments apart (pink and olive bricks, red and brown wood stripes, a purple joint).
  float paletteWeight = 0.0f;
  /// Which colours the palette prior holds together (graph/palette_prior.hpp): each ramp, or all
  /// the graph's colours as one group.
  PaletteScope paletteScope = PaletteScope::Ramps;
  /// Departures from the defaults' colour relations that cost nothing (paletteLoss's deadZone;
  /// kPaletteDrawDeadZone covers the library's own random draws).
  float paletteDeadZone = 0.0f;
  /// Graph parameters kept at their start values: names, or a prefix followed by '*' ("grain_*":
  /// the library's octave amplitudes). Selection's short fits hold the octaves, so a finalist is
  /// judged at its designed grain (graph/README.md, "Coverage").
  std::vector<std::string> heldParameters;
  /// A line search over the held roughness (this many values log-spaced over its allowed range,
  /// with the state's maps and UV transform, at full resolution) before the fine steps (or after
  /// the steps without a coarse phase); < 2 = none. The Adam steps alone moved the one scalar
  /// slowly and stopped where the data term is flat.
  int roughnessCandidates = 0;
  /// Where the light predicts no highlight on the part (an empty highlight region, with the
  /// highlight term on) nothing in the photo tells how glossy it is, and the fit explained the
  /// photo's noise and texture variance with specular sparkle: the prior's weight is multiplied by
  /// this there.
  float noHighlightPriorScale = 10.0f;
  bool fitUvContinuous = true;     ///< Adam also moves the UV transform between searches
  int uvSearchEvery = 50;          ///< iterations between discrete searches (0: only before the first)
  int searchRotations = 24;        ///< over [0, 360) degrees
  int searchLogScales = 9;         ///< over [logScaleMin, logScaleMax] (absolute)
  int searchOffsets = 1;           ///< n x n offsets over [0, 1)^2 (1: keep the current offset)
  float logScaleMin = -1.6f, logScaleMax = 1.6f;
  int refineSteps = 2;             ///< coarse-to-fine: halvings of the search steps around the best
  /// The spectral prior (optim/uv_spectrum.hpp): before the first search the UV scale is read from
  /// the photo's spectrum against the graph's (default-parameter) albedo; where that estimate is
  /// clear, the searches try only log-scales within +-spectrumScaleWindow of it (3 of them, then
  /// the refinement), every rotation as before, and Adam keeps the log-scale within that window.
  /// 0 = off: the whole [logScaleMin, logScaleMax] grid.
  /// The texture statistics alone can prefer a wrong period at the default parameters (wider
  /// planks with faint gaps), and the fit then adapts the parameters to it.
  float spectrumScaleWindow = 0.1f;
  /// The layer's lobe filter (RenderLayerParams::lobeFilter; 0 = off): glossy lobes widened to
  /// the spacing of the directions the layer sums them over.
  float lobeFilter = 0.0f;
  int specularSub = 1;             ///< the layer's specularSub during the Adam iterations
  int searchSpecularSub = 1;       ///< the layer's specularSub during searches (cheaper)
  /// Coarse to fine in image space: the part is also seen at 1/2, 1/4, ... of the photo's
  /// resolution (ps::downsamplePartGeometry; the texture loss on the photo downsampled the same
  /// way). The first maxIterations - fineIterations Adam steps run `coarseLevels` halvings down,
  /// the last `fineIterations` at full resolution (no searches there); the UV searches compare at
  /// `searchLevels` halvings: the grid is ranked there, its `searchKeep` best are compared again at
  /// full resolution and the refinement runs there. A level is used only if it keeps
  /// >= minLevelPixels pixels (else the deepest level that does; a small part is fitted at full
  /// resolution throughout). 0 = full resolution throughout.
  int coarseLevels = 1;
  int searchLevels = 2;
  int searchKeep = 8;
  int fineIterations = 40;
  /// The learning rates of the full-resolution steps after a coarse phase, relative: they refine a
  /// fitted state, and Adam's first steps at the full rate moved it away (balanced, 6 graphs x 2
  /// lightings: 0.25 lowered the mean texture distance to the truth by 15 % against 1).
  float fineLearningRateScale = 0.25f;
  int minLevelPixels = 1500;
  PlateauOptions plateau{20, 2e-3, 60};
  int restarts = 0;                ///< random starts probed besides the defaults
  int restartProbeIterations = 30; ///< iterations each start gets before the best is continued
  float restartSpread = 0.5f;
  uint64_t seed = 1;
  /// Called after every Adam step and during searches (progress bars, checkpoints, cancellation);
  /// returning false stops the fit there, with the best state so far and PartFitResult::cancelled
  /// set. Not part of what a preset decides, and not a fit parameter (a fit's cache key leaves it
  /// out).
  std::function<bool(const PartFitProgress&)> onProgress;

  /// "paper": 1000 iterations, maps 256, 72 rotations x 32 log-scales x 5 x 5 offsets every 50
  /// iterations (the caller renders at 320 x 240; every step at full resolution, the search's grid
  /// ranked at half resolution and its best 16 compared at full resolution; no spectral prior).
  /// "balanced", "fast": chosen by measurement (modules/optim/README.md), the spectral prior on.
  static PartFitOptions preset(const std::string& name);
  bool IsValid(std::string* error) const;
};

/// The loss and its terms at one state (the formula at the top of this file).
struct PartFitLosses {
  double loss = 0, lossStat = 0, lossTexture = 0;
  double lossPlacement = 0;                                  ///< L_place (0 if off)
  double lossPrior = 0, lossHighlight = 0, lossCeiling = 0;  ///< L_prior, L_hl, L_ceil (0 if off)
  double lossPalette = 0;                                    ///< L_palette (0 if off)
  /// the weighted terms that compare the render with the photo (stat, texture, placement,
  /// highlight): `loss` less the regularisers on the parameters (prior, ceiling, palette). What held-back
  /// pixels test: a regulariser scores the fitted values, not how they explain other pixels.
  double lossData = 0;
};

/// A fit's result; its loss terms (PartFitLosses) are at the returned values.
struct PartFitResult : PartFitLosses {
  std::vector<float> values;       ///< graph values (MaterialGraph::values() layout)
  UvParams uv;
  float roughness = 0.5f;          ///< the fitted mean roughness
  float roughnessScale = 1.0f;     ///< multiplies the graph's roughness map to that mean
  RoughnessPrior roughnessPrior;  ///< the prior used (when roughnessPriorWeight > 0)
  int highlightPixels = 0;        ///< pixels of the highlight region at full resolution (0: none)
  /// fraction of the fitted albedo map's texels >= 0.99 per channel; `albedoPinned` when a
  /// channel has more than 20 % of its texels there (logged as a warning: light and albedo traded)
  cv::Vec3f albedoAtCeiling = cv::Vec3f(0, 0, 0);
  bool albedoPinned = false;
  double initialLoss = 0, initialTextureLoss = 0;  ///< at the start (defaults, initial UV)
  int iterations = 0;              ///< Adam steps taken (all starts)
  int searches = 0;                ///< discrete UV searches run
  int candidates = 0;              ///< UV candidates evaluated
  double seconds = 0;
  double searchSeconds = 0;        ///< of which in the discrete UV searches
  bool stoppedOnPlateau = false;
  bool cancelled = false;          ///< onProgress returned false
  UvSpectrumEstimate spectrum;  ///< the spectral prior's estimate (ok false: not used)
  double spectrumSeconds = 0;   ///< of searchSeconds, in the spectral prior
  /// loss per iteration of the continued start, at the resolution that iteration ran at (the
  /// coarse iterations' losses are not comparable with the fine ones')
  std::vector<double> history;
  int coarseIterations = 0;        ///< how many of `history`'s entries ran at a coarse level
  cv::Mat render;                  ///< CV_32FC3 the final render of the part (image size)
};

/// Masked statistics loss (Eq. 6-8, normalised as above) and its gradient with respect to the
/// render (CV_32FC3, photo size, zero outside `pixels`; written when gradRender != nullptr).
/// `photoNoise`: the photo's pixel noise per channel (TextureLossTarget::photoNoise), its variance
/// taken off the photo's (a render has no noise).
double statLoss(const cv::Mat& photo, const cv::Mat& render, const std::vector<cv::Point>& pixels,
                cv::Mat* gradRender, const cv::Vec3d& photoNoise = {0, 0, 0});

/// Fits `graph` (a copy is made; its current values are the start) to `photo` over the part.
/// @param geometry the part in the photo's view (its mask = the loss's mask)
/// @param photo    CV_32FC3 linear RGB, geometry.imageSize
/// @param target   the texture-loss target built from `photo` and the same mask
/// @param initialUv start of the UV transform (the OBJ mapping: identity)
PartFitResult fitPart(const MaterialGraph& graph, const PartGeometry& geometry, const cv::Mat& photo,
                      const TextureLossTarget& target, const PartFitOptions& options,
                      const UvParams& initialUv = {});

/// The loss of a fitted state (`state`'s values, UV transform and held roughness, as fitPart
/// returned them) on a part's geometry that the fit may not have seen: other pixels of the part
/// (held back), another view. No steps and no search; fills the loss terms and the render,
/// values / uv / roughness / roughnessScale are the state's.
/// @param graph the graph the state's values belong to
/// @param matchMeans the render's channel means over the geometry's pixels are first scaled to
///                   the photo's (as the UV search compares patterns, not colours)
PartFitResult scorePart(const MaterialGraph& graph, const PartFitResult& state,
                        const PartGeometry& geometry, const cv::Mat& photo,
                        const TextureLossTarget& target, const PartFitOptions& options,
                        bool matchMeans = false);

/// The same for maps that no graph made (a photographed material's, resampled to a power of two:
/// what the fit's loss says of the true texture): the loss terms and the render of `maps` under
/// `uv` with the held roughness `roughness`, the roughness prior of `category` ("" = none).
PartFitResult scoreMaps(const MaterialMaps& maps, const std::string& category, const UvParams& uv,
                        float roughness, const PartGeometry& geometry, const cv::Mat& photo,
                        const TextureLossTarget& target, const PartFitOptions& options,
                        bool matchMeans = false);

}  // namespace ps

// Emitter intensities from photos (paper section 3.4, "globally consistent lighting").
//
// With N emitters (area lights, plus the environment as one more "light") and V views, the
// renderer draws every light alone at unit radiance: I_{v,k}, linear RGB. The photo of view v is
// modelled as
//
//     P_v(p) = e_v * sum_k x_k (.) I_{v,k}(p)          x_k in R^3, x_k >= 0, e_0 = 1
//
// with (.) the per-channel product: 3 x N non-negative coefficients (the paper's 3 x (N + 1)) and
// one exposure per further view. Each channel is a non-negative least-squares problem over the
// usable pixels (where geometry and photo agree, not saturated, not on an emitter); exposures and
// intensities are solved alternately when there are several views. A light whose coefficient
// ends at zero in every channel, or whose share of the rendered energy is below
// `dropShare`, is dropped (its radiance set to 0) and the rest re-solved.
//
// A light the photos show directly (its emitting surface, or the sky and landscape through a
// window that opens onto it) is pinned there: those pixels carry no albedo, so where at least
// `directMinPixels` of them are usable its intensity is their least-squares fit alone, and only
// the other lights are solved over the rest. Without the pin the solve trades the window's own
// pixels against surfaces whose albedos are guesses (round 0) or were fitted under the previous
// lights: on the blender-room example the forest through the window rendered at 0.59 / 0.78 /
// 0.96 of the photo (R / G / B; 1.01 pinned), darker still with a second view that adds
// surface pixels but not the window.
//
// Where the per-light renders use guessed reflectances (the parts still to be fitted), a region
// map gives each part a free RGB factor f_r on its guess: P_v(p) = e_v f_r(p) (.) sum_k x_k (.)
// I_{v,k}(p). The light is then read from how the shading varies within each part (a wall
// darkening away from a lamp), not from the guesses' brightness against each other (a guess of
// photo median x pin assumes that every part gets the same light, which makes the lamp over the
// brightest part look weak). Lights, exposures and factors are solved alternately. A common scale
// of light and reflectance per channel is not observable from the shading alone: the gauge keeps
// the factors' pixel-weighted geometric mean at 1 per channel, so it stays as the guesses set it.
// The guesses (photo median x pin) carry the light's colour, so a warm lamp came out blue and the
// walls red (blender-room example: lamps 22 / 24 / 26 and 21 / 25 / 31 against the truth's
// 30 / 28 / 24; wall 0.76 / 0.64 / 0.46 against 0.64 / 0.60 / 0.53). A pinned light's colour is
// measured (its own pixels carry no reflectance), so where its light is at least 5 % of the
// photos' energy the gauge is one scale over the channels instead: the colour of light and
// reflectance follows the pinned light, the level still the guesses (the window's level sets it
// poorly: its light on the surfaces goes through the coarse geometry and the guessed
// interreflections; left free, the albedos came out 13 % low). On that example (`photoscene run
// .../scene.json --preset fast`, which uses it in the final light solve only): lamps 27 / 24 / 21
// and 27 / 26 / 23, wall 0.66 / 0.63 / 0.56; over the 9 parts of at least 2000 px the albedos'
// mean |log(fitted / true)| 0.156 -> 0.062, their colour (that with its mean over the channels
// removed) 0.133 -> 0.017.
// The pinned light constrains the colour weakly (6 % of the light on the parts there), so with
// this gauge the alternation has not converged at `maxAlternations` = 200: the result is the
// 200th iterate from factors of 1, an early stop that keeps the factors near the guesses'
// level. Run to convergence (about 900 alternations; measured with this gauge in both light
// solves of the pipeline) the same example gives lamps 30 / 25 / 21 and 35 / 26 / 20, the large
// parts' albedo colour 3x further from the truth than at 200 (still 4x closer than the
// per-channel gauge) and novel1 sRGB RMSE 18.44 (200: 18.04; per-channel gauge, converged by
// 100: 18.06); the per-channel gauge's result does not move with the cap.
//
// Emitters of given radiance are a known term G_v of the model, not a subtraction from the photo:
// P_v = e_v f_r (.) (G_v + sum_k x_k (.) I_{v,k}). Taking G_v off the photo assumed exposure 1 and
// the guessed reflectances: on the blender-room example with both lamps given and a second view,
// the second view's exposure came out 3.6 (truth 1.0; residual 85 % of the photo's RMS).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "photoscene/core/math.hpp"

namespace ps::lighting {

/// Non-negative least squares, min ||A x - b||_2 subject to x >= 0 (Lawson and Hanson 1974,
/// active set). Deterministic; returns the solution (zeros where the bound is active).
Eigen::VectorXd nnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, int maxIterations = 0);

/// The data of one view.
struct ViewLightData {
  cv::Mat photo;                 ///< CV_32FC3 linear RGB
  cv::Mat mask;                  ///< CV_8UC1: pixels usable for the fit (non-zero)
  std::vector<cv::Mat> perLight; ///< per light, CV_32FC3 render at unit radiance, photo's size
  /// Optional, per light (empty, or one per light; an empty Mat: none): CV_8UC1, the pixels
  /// where the light itself is seen (its emitting surface or an opening onto it). They need not
  /// lie in `mask` (which a caller may narrow to other evidence); saturated and non-finite
  /// pixels are left out as there.
  std::vector<cv::Mat> direct;
  /// Optional: CV_32SC1, per pixel the region (a part, the same index in every view) whose
  /// reflectance is only guessed in the per-light renders, -1 where it is known (or none). Each
  /// region gets its own RGB factor on the guess (LightSolution::regionFactor), so the light is
  /// read from how the shading varies within each region, not from how bright the guesses are
  /// against each other.
  cv::Mat regions;
  /// Optional: CV_32FC3, the light of the emitters whose radiance is given (not solved), at that
  /// radiance, rendered with the same reflectances as `perLight`. It is part of the model, not
  /// taken off the photo: P_v = e_v f_r (.) (G_v + sum_k x_k (.) I_{v,k}), so the view's exposure
  /// and a region's factor scale it as they scale the solved lights. A light of known radiance
  /// also fixes the scale per channel that the factors' gauge otherwise sets (LightSolution::
  /// regionFactor).
  cv::Mat given;
};

struct SolveOptions {
  bool perViewExposure = true;   ///< solve e_v for views 1..V-1 (view 0 is the reference)
  /// the factors' alternation converges slowly (about 100 with the per-channel gauge; with a
  /// pinned light's colour it stops here unconverged, which the results above depend on)
  int maxAlternations = 200;
  double tolerance = 1e-7;       ///< relative residual change that ends the alternation
  /// Photo values at or above this (linear) are treated as clipped and left out; 8-bit photos
  /// clip at 1.0.
  double saturation = 0.99;
  int maxSamplesPerView = 40000; ///< usable pixels are subsampled on a fixed grid above this
  double dropShare = 0.002;      ///< drop lights contributing less than this share of energy
  /// A light seen directly on at least this many usable pixels (all views) is pinned to them
  /// (ViewLightData::direct); 0: never.
  int directMinPixels = 200;
  /// Where pinned lights send at least 5 % of the light on the regions, their measured colour
  /// sets the colour of light and reflectance (the gauge is one scale over the channels);
  /// false: one scale per channel whatever the lights (the colour as the guesses set it).
  bool pinnedLightSetsColour = true;
  bool IsValid(std::string* error) const;
};

struct LightSolution {
  std::vector<Vec3d> intensity;  ///< per light: the multiplier on its unit-radiance render
  std::vector<double> exposure;  ///< per view (exposure[0] = 1)
  std::vector<bool> dropped;     ///< per light
  std::vector<int> directPixels; ///< per light: usable pixels where it is seen directly
  std::vector<bool> pinned;      ///< per light: its intensity came from those pixels alone
  /// per region (ViewLightData::regions): the factor on its guessed reflectance, RGB. The
  /// gauge: per channel the pixel-weighted geometric mean over the regions is 1; where pinned
  /// lights send at least 5 % of the photos' energy, over the channels together (their colour
  /// sets the factors' colour); where given light (ViewLightData::given) does, none (its known
  /// radiance sets the scale).
  std::vector<Vec3d> regionFactor;
  double residualRms = 0;        ///< RMS of the model minus the photo over the samples
  double photoRms = 0;           ///< RMS of the photo over the same samples (for scale)
  int samples = 0;
  int alternations = 0;
  std::string summary() const;
};

/// Solves for every light's RGB intensity (and per-view exposure). Throws ps::Exception when no
/// view has a usable pixel or sizes disagree.
LightSolution solveLights(const std::vector<ViewLightData>& views, const SolveOptions& options = {});

/// The pixels of `mask` whose renders solveLights reads for a view with this photo (CV_8UC1,
/// 255 there): the usable ones (photo finite, >= 0 and below options.saturation), every k-th in
/// raster order where there are more than options.maxSamplesPerView, provided the renders are
/// finite there (PathTracer's are). A caller that traces only these pixels and those of
/// ViewLightData::direct (RenderOptions::pixels), and passes the result as the view's `mask`,
/// gets the solution that whole renders give.
cv::Mat solvePixels(const cv::Mat& photo, const cv::Mat& mask, const SolveOptions& options = {});

}  // namespace ps::lighting

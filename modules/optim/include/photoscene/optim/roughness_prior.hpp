// Plausible roughness and albedo for the material fits (issue 17, item 5): what keeps a fit from
// explaining a matte photo with a mirror-like surface, or pinning an albedo channel at 1.0.
//
// - A roughness prior per graph category: a Gaussian in log-roughness and a hard range (fabric and
//   carpet are never glossy). The numbers come from the roughness maps of the photographed CC0
//   materials of the real-texture yardstick's `tune` half (modules/optim/README.md, "Roughness
//   priors"); categories without a measured material are stated assumptions.
//     L_prior(r) = 0.5 ((ln r - mu) / sigma)^2
// - A highlight term: the pixels where the part's incident light predicts a specular highlight
//   (the layer's specular-only render of a glossy surface is bright against its diffuse render)
//   are found once per part; the term compares how much brighter those pixels are than the part
//   as a whole, in the photo and in the render:
//     c(I) = ln(mean_H lum(I) + eps) - ln(mean_P lum(I) + eps),   L_hl = (c(photo) - c(render))^2
//   A highlight in the photo that the render lacks pulls roughness down; a highlight the render
//   predicts and the photo lacks pushes it up. The contrast is invariant to the albedo's and the
//   light's level, so it does not fight the colour terms. No highlight region: the term is 0.
// - An albedo ceiling: a soft barrier on albedo texels above `knee`, so that a fit does not pin a
//   channel at 1.0 (a sign that light and albedo traded against each other; it is also logged).
//     L_ceil(A) = mean over texels and channels of (max(0, a - knee) / (1 - knee))^2
//
//   const ps::RoughnessPrior prior = ps::roughnessPriorFor("fabric");  // r in [0.45, 1]
//   double g = 0;
//   const double l = ps::roughnessPriorLoss(prior, 0.3f, &g);          // > 0, g < 0 (pushes up)
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/render/render_layer.hpp"

namespace ps {

/// A roughness prior: ln r ~ N(logMean, logSigma^2), and r kept in [min, max].
struct RoughnessPrior {
  std::string category;    ///< the category it was made for ("" = the generic prior)
  float logMean = -0.73f;  ///< mean of ln r
  float logSigma = 0.73f;  ///< standard deviation of ln r (> 0)
  float min = 0.04f;       ///< the fit keeps r in [min, max]
  float max = 1.0f;
  /// the roughness at the prior's mode in log space, exp(logMean)
  float center() const;
};

/// The prior of a graph category of scene-format.md section 4 (`wood`, `fabric`, ...); an unknown
/// or empty category, and `homogeneous`, get the generic prior (all measured materials).
RoughnessPrior roughnessPriorFor(const std::string& category);

/// 0.5 ((ln r - mu) / sigma)^2 at r (clamped to >= 1e-4); d/dr into *grad when given.
double roughnessPriorLoss(const RoughnessPrior& prior, float roughness, double* grad);

/// Options of the highlight region.
struct HighlightOptions {
  float glossyRoughness = 0.12f;  ///< the roughness whose highlight is predicted
  /// a pixel is in the region where the specular-only render exceeds this fraction of the diffuse
  /// render of a white albedo (the specular of a dielectric is ~4 % of the light: a highlight this
  /// bright against a mid-grey albedo is visible)
  float minRatio = 0.25f;
  /// the region must hold at least this many pixels and this fraction of the part, and at most
  /// `maxFraction` of it (else the light predicts no localised highlight: an empty region)
  int minPixels = 12;
  float minFraction = 0.004f;
  float maxFraction = 0.5f;
};

/// The part's pixels (a subset of geometry.pixels) where the incident light predicts a specular
/// highlight on a glossy surface; empty when it predicts none. Uses the layer's render with the
/// geometry's incident-light grid (flat normals, no maps).
std::vector<cv::Point> highlightRegion(const PartGeometry& geometry,
                                       const HighlightOptions& options = {});

/// L_hl above, over `pixels` (the part) and `highlight` (a subset); 0 when `highlight` is empty.
/// d L / d render (CV_32FC3, photo size) is added into *gradRender (times `weight`) when given
/// (allocated and zeroed when empty).
double highlightLoss(const cv::Mat& photo, const cv::Mat& render,
                     const std::vector<cv::Point>& pixels, const std::vector<cv::Point>& highlight,
                     cv::Mat* gradRender, double weight = 1.0);

/// L_ceil above on an albedo map (CV_32FC3); d L / d albedo added into *gradAlbedo (times
/// `weight`; allocated and zeroed when empty) when given. knee in (0, 1).
double albedoCeilingLoss(const cv::Mat& albedo, float knee, cv::Mat* gradAlbedo,
                         double weight = 1.0);

/// Fraction of an albedo map's texels whose channel c is >= `level`, per channel.
cv::Vec3f albedoFractionAtCeiling(const cv::Mat& albedo, float level = 0.99f);

}  // namespace ps

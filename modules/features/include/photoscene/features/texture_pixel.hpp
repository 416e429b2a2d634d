// Pixel-scale structure of an image's luminance: how the finest grain is correlated from one
// pixel to the next. A photograph's grain (surface, sensor, demosaicing, the resampling that made
// the view) is correlated over a pixel or two; a procedural graph's pixel-scale noise is white, and
// its patterns' edges are sharp. The Gabor bank of texture_descriptor.hpp sees periods of 2.9
// pixels and up and cannot tell the two apart; the local binary patterns of eval's texture
// distance can (a white grain reads as isolated spots, the photograph's as short edges). These
// statistics are what a loss can see of that, with an analytic gradient.
//
// On the luminance Y (Rec. 709) of a CV_32FC3 image of W x H pixels: the residual
// R = Y - box3(Y) (Y minus its 3 x 3 mean) on the pixels at least 1 from the border, and over
// Omega, the pixels at least 3 from the border, A = R - mean_Omega(R),
//   v     = mean_Omega(A^2) + delta,
//   contrast       = sqrt(v) / mu   (mu = the image's mean luminance, floored),
//   correlation_d  = mean_Omega(A(p) A(p + d)) / v,
// d in (1,0), (0,1), (1,1), (1,-1), (2,0), (0,2), where delta = 1e-6 mu_target^2 in the loss (a
// flat render's correlations stay finite) and 0 in pixelStructure(). Light level cancels in all
// seven.
//
// Loss against a target's statistics (each entry's square, the mean of the seven, times weight):
//   ( log((contrast + 1e-3) / (contrast_t + 1e-3)) )^2  and  (correlation_d - correlation_t,d)^2.
// The log keeps a far-off start (a graph whose grain is off: contrast 0) from dominating the
// texture loss it is added to.
//
//   ps::PixelStructure t = ps::pixelStructure(photoView);
//   cv::Mat grad;                                          // d loss / d render, CV_32FC3
//   double l = ps::pixelStructureLoss(render, t, 1.0, &grad);
#pragma once

#include "photoscene/features/texture_loss.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <vector>

namespace ps {

struct PixelStructure {
  static constexpr int kLags = 6;
  /// The lags (dx, dy) of `correlation`.
  static constexpr int kLag[kLags][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}, {2, 0}, {0, 2}};
  double contrast = 0;                      ///< std of the residual over the mean luminance
  std::array<double, kLags> correlation{};  ///< the residual's correlation at each lag
  double mean = 0;                          ///< the image's mean luminance (unfloored)
  int pixels = 0;                           ///< pixels in Omega (0: the image is under 7 x 7)
};

/// The statistics of `image` (CV_32FC3, linear RGB, finite). All 0 when it is smaller than
/// 7 x 7 pixels.
PixelStructure pixelStructure(const cv::Mat& image);

/// weight x the loss above between `image` and `target`. With `grad`, d loss / d image is added
/// to *grad (allocated as zeros, CV_32FC3 of image's size, when empty). 0 (and no gradient) when
/// the image is smaller than 7 x 7 pixels.
double pixelStructureLoss(const cv::Mat& image, const PixelStructure& target, double weight,
                          cv::Mat* grad = nullptr);

/// Finite-difference check of pixelStructureLoss's gradient on the three channels of `pixels`
/// (central differences at `step` and 2 `step`; texture_loss.hpp's summary).
TextureLossGradientCheck checkPixelStructureGradient(const cv::Mat& image,
                                                     const PixelStructure& target, double weight,
                                                     const std::vector<cv::Point>& pixels,
                                                     double step = 1e-3);

}  // namespace ps

// The pattern's placement: a pixel term between a render and the (aligned) photo after a low-pass,
// the stand-in for the paper's Eq. 9 (a masked per-pixel distance of feature maps after the
// Eq. 1 warp). The texture statistics are blind to where a pattern lies (a UV offset moves every
// plank seam and grout line but changes no statistic); this term sees it, at a coarse scale only,
// so pixel noise and fine grain do not matter.
//
//   b(x)  = G_sigma(M L)(x) / G_sigma(M)(x)        masked low-pass of the luminance
//           (normalized convolution: the mask's edge is not read as a dark border),
//           L = 0.2126 R + 0.7152 G + 0.0722 B, M the mask (0 / 1), G a Gaussian, zero border
//   c     = b - mean_M(b),  sigma_b^2 = mean_M(c^2) + eps^2,  eps = 1e-3 * mean photo luminance
//   loss  = 1 - rho,  rho = mean_M(c_render * c_photo) / (sigma_render * sigma_photo)
//
// rho is the correlation of the two low-passed luminances over the mask: the loss is in [0, 2],
// invariant to the render's brightness and contrast (the statistics losses match those), and
// 0 when the patterns lie in the same place. Its gradient with respect to the render's pixels is
// exact (the Gaussian is symmetric: its own adjoint) and zero outside the mask.
//
//   ps::PlacementLossTarget target(alignedPhoto, alignedMask, {2.0});
//   cv::Mat grad;
//   double loss = ps::placementLoss(target, render, &grad);   // grad: d loss / d render
#pragma once

#include "photoscene/features/texture_loss.hpp"

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace ps {

struct PlacementLossOptions {
  /// Standard deviation of the low-pass in pixels (in [0.5, 32]): structure finer than about
  /// 2 sigma (noise, grain) does not count.
  double sigma = 2.0;
  bool IsValid(std::string* error) const;
};

/// The photo side: the mask's crop, the low-pass of the mask, the photo's normalized low-pass.
class PlacementLossTarget {
 public:
  /// @param photo CV_32FC3, linear RGB, non-negative, finite: the photo after the Eq. 1 warp
  /// @param mask  CV_8UC1, photo's size, non-zero = the part (the aligned mask); non-empty
  /// @throws ps::Exception for wrong types or sizes, a non-finite photo, an empty mask
  PlacementLossTarget(const cv::Mat& photo, const cv::Mat& mask,
                      const PlacementLossOptions& options = {});
  cv::Size imageSize() const { return size_; }
  cv::Rect crop() const { return crop_; }
  const PlacementLossOptions& options() const { return options_; }

 private:
  friend double placementLoss(const PlacementLossTarget&, const cv::Mat&, cv::Mat*, float, bool);
  PlacementLossOptions options_;
  cv::Size size_;
  cv::Rect crop_;        // the mask's bounding box grown by the kernel radius
  cv::Mat mask_;         // CV_32F 0 / 1, crop size
  cv::Mat invCoverage_;  // 1 / G(M) on the mask, 0 elsewhere
  cv::Mat photoHat_;     // c_photo / sigma_photo on the mask, 0 elsewhere (CV_64F)
  int count_ = 0;
  double eps_ = 0.0;
};

/// The placement loss of `render` against the target; with gradRender, d(gradScale * loss) /
/// d render (CV_32FC3, image size; zero outside the mask), written or, with accumulate and a
/// gradRender of the right size and type, added.
/// @param render CV_32FC3, target.imageSize(), finite
double placementLoss(const PlacementLossTarget& target, const cv::Mat& render,
                     cv::Mat* gradRender = nullptr, float gradScale = 1.0f,
                     bool accumulate = false);

/// Central differences (steps step and 2 step, as checkTextureLossGradient) of placementLoss at
/// pixels x channels against its analytic gradient.
TextureLossGradientCheck checkPlacementLossGradient(const PlacementLossTarget& target,
                                                    const cv::Mat& render,
                                                    const std::vector<cv::Point>& pixels,
                                                    double step = 1e-3);

}  // namespace ps

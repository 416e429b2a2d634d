// Private: forward and backward of the Portilla-Simoncelli-style statistics (texture_ps.hpp) on a
// forward pass of the Gabor pyramid (gabor_pyramid.hpp).
#pragma once

#include "gabor_pyramid.hpp"
#include "photoscene/features/texture_ps.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace ps::features_detail {

/// The lags of a (2 radius + 1)^2 window counted once (texture_ps.hpp's order).
std::vector<cv::Point> psLags(int radius);

/// What depends on the mask only: the pair weights sum_x u(x) u(x + d) per level and lag.
struct PsMask {
  int radius = 0;  // max(lowpassRadius, magnitudeRadius)
  std::vector<std::vector<double>>
      pair;  // per level: (2 radius + 1) x (radius + 1), [dy][dx + radius]
  double pairAt(int level, cv::Point d) const {
    return pair[level][d.y * (2 * radius + 1) + d.x + radius];
  }
};
PsMask makePsMask(const MaskPyramid& pyramid, const TextureDescriptorOptions& options,
                  const TexturePsOptions& psOptions);

/// Forward results kept for backward.
struct PsState {
  std::vector<double> values;  // texturePsLayout().length entries
  std::vector<cv::Mat> cz;     // per level: centered z_s (CV_64F)
  std::vector<cv::Mat> cm;     // per band: centered magnitude (CV_64F)
  std::vector<cv::Mat> cu;     // per band of levels 1..S-1: centered expand(mag) at s - 1
  cv::Mat opp;                 // crop, CV_64FC3: opponent colours (0 outside the mask)
};

/// The statistics of a forward pass that kept its intermediates (forwardDescriptor(keep = true)).
void forwardPs(const ForwardState& state, const MaskPyramid& pyramid, const PsMask& psMask,
               const GaborBank& bank, const TextureDescriptorOptions& options,
               const TexturePsOptions& psOptions, PsState& ps);

/// Adds d out / d (magnitudes, z, crop pixels) for d out / d values = gradValues to `extra`
/// (its vectors are sized here; entries of groups whose gradients are all 0 are skipped).
void backwardPs(const ForwardState& state, const MaskPyramid& pyramid, const PsMask& psMask,
                const GaborBank& bank, const TextureDescriptorOptions& options,
                const TexturePsOptions& psOptions, const PsState& ps,
                const std::vector<double>& gradValues, ExtraGradients& extra);

}  // namespace ps::features_detail

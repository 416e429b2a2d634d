// Portilla-Simoncelli-style joint statistics on the masked Gabor pyramid of texture_descriptor.hpp:
// what the marginal band statistics cannot see (periodicity, lines and edges, colour structure).
//
// Computed on the same crop, centered luminance pyramid z_s, band magnitudes m_{s,k} = |r_{s,k}|
// and statistics weights w_s (level s, normalized to sum 1) as the descriptor. For a map f on
// level s, c = f - sum_x w_s f is the weighted-centered map, and all sums below run over the crop
// with zero beyond it. Every entry is a correlation coefficient (unitless, in [-1, 1] up to the
// regularizer eps = options.epsilon) except the colour means and standard deviations.
//
// Layout (S = numScales, K = numOrientations, lags(R) = 2 R (R + 1): the lags (dx, dy) of the
// (2R+1)^2 window with dy > 0, or dy = 0 and dx > 0 (the autocorrelation is point-symmetric),
// in row order dy = 0..R, dx = -R..R):
//   autoLowpass  [S x lags(lowpassRadius)]   per level s: rho_d of c = centered z_s, the low-pass
//                  image at level s. Periodicity (tile and plank spacing up to 3 * 2^s pixels):
//                  rho_d = A_d / (A_0 + eps^2),  A_d = sum_x q(x) q(x + d) / sum_x u(x) u(x + d),
//                  q = u c, u = w_s (pairs count by the product of their weights, so only pairs
//                  with both pixels inside the mask count). A lag whose pair weight is below 5 %
//                  of lag 0's (the region is too small for it) reads 0.
//   autoMagnitude [S x K x lags(magnitudeRadius)]  the same of each band's centered magnitude:
//                  how far an edge or line of that band continues (its length and spacing).
//   crossOrientation [S x K(K-1)/2]  per level, pairs (k < l) in row order: weighted correlation
//                  rho(c_k, c_l) = sum w c_k c_l / sqrt((sum w c_k^2 + eps^2)(sum w c_l^2 + eps^2))
//                  of the centered magnitudes: corners and crossings (grids: high) against lines
//                  of one direction (low).
//   crossScale   [(S-1) x K x K]  per level s < S-1, (k at s, l at s+1): rho(c_{s,k}, centered
//                  expand(m_{s+1,l})), expand = the pyramid's upsampling (zero insertion, the
//                  [1 4 6 4 1] blur, times 4): magnitude only (not P&S's phase-doubled coarse
//                  band). Sharp edges (grout lines, plank seams) are seen at several octaves at
//                  once; smooth noise is not.
//   colour       [9]  in the opponent space O1 = (R - G) / sqrt 2, O2 = (R + G - 2B) / sqrt 6,
//                  O3 = (R + G + B) / sqrt 3 over the mask pixels (equal weights): means of
//                  O1..O3, standard deviations sqrt(var + eps^2) of O1..O3 (linear units), and
//                  the correlations (O1, O2), (O1, O3), (O2, O3).
//
//   ps::TexturePsOptions po;
//   std::vector<float> s = ps::computeTexturePsStatistics(photo, mask, {}, po);
//   float periodicity = s[ps::texturePsLayout({}, po).autoLowpass + 3];  // level 0, lag (0, 1)
#pragma once

#include "photoscene/features/texture_descriptor.hpp"

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace ps {

struct TexturePsOptions {
  /// Half-width of the lag window of the low-pass autocorrelation (lags(R) entries per level).
  int lowpassRadius = 3;
  /// Half-width of the lag window of the band magnitudes' autocorrelation.
  int magnitudeRadius = 2;
  bool IsValid(std::string* error) const;
};

/// Offsets of the groups in the statistics vector, and its length.
struct TexturePsLayout {
  int autoLowpass = 0, autoMagnitude = 0, crossOrientation = 0, crossScale = 0, color = 0;
  int length = 0;
};
TexturePsLayout texturePsLayout(const TextureDescriptorOptions& descriptor,
                                const TexturePsOptions& options);
/// Number of lags of a (2 radius + 1)^2 window counted once: 2 radius (radius + 1).
int texturePsLagCount(int radius);

/// The statistics of the masked region (layout above).
/// @param image CV_32FC3, linear RGB (R first), non-negative, finite
/// @param mask  CV_8UC1, same size, non-empty (an empty mask throws ps::Exception)
std::vector<float> computeTexturePsStatistics(const cv::Mat& image, const cv::Mat& mask,
                                              const TextureDescriptorOptions& descriptor = {},
                                              const TexturePsOptions& options = {});

}  // namespace ps

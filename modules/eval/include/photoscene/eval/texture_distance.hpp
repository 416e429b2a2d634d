// A texture distance that is not part of any loss: does a fitted part *look like* the photo,
// without asking that the two be pixel-aligned (a procedural graph never reproduces the photo's
// texture pixel for pixel; a pixel RMSE then prefers a flat median colour).
//
// Each masked region is described by three normalised histograms, all on luminance
// Y = 0.2126 R + 0.7152 G + 0.0722 B of the linear image:
//
//   lbp       uniform, rotation-invariant local binary patterns (Ojala et al. 2002, LBP^riu2 with
//             P = 8 bilinear samples) at radii 1, 2 and 4 pixels, each on Y blurred by a Gaussian
//             of sigma = radius / 2 (smoothed multi-scale LBP: the radius-1 codes of a noisy render
//             are not dominated by its noise); 10 bins per radius, over the masked pixels whose
//             circle lies inside the image. Invariant to any monotonic change of brightness.
//   spectrum  the power spectrum of the masked region: Y / (masked mean of Y) - 1 inside the mask,
//             0 outside, times a Hann window over the mask's bounding box, zero-padded to a
//             square DFT; the power summed into 6 radial bins (log-spaced from 1/64 to 1/2 cycle
//             per pixel) x 4 orientation bins (0, 45, 90, 135 degrees, +-22.5); the fractions of
//             the total. Sees period, orientation and grain; invariant to a global brightness
//             scale.
//   contrast  the histogram of Y / (masked mean of Y) in 16 bins over [0, 2.5) (values above in
//             the last bin): how much the texture varies, which LBP and spectrum fractions do not
//             see. Invariant to a global brightness scale.
//
// The distance is the mean of the three blocks' chi-square distances
//   chi2(a, b) = 1/2 sum_i (a_i - b_i)^2 / (a_i + b_i)   (terms with a_i + b_i = 0 are 0)
// (the LBP block is the mean over its radii), so each block and the total lie in [0, 1]:
// 0 for identical histograms, 1 for histograms with disjoint support.
//
//   double d = ps::eval::textureDistance(photo, partMask, render, partMask).total;
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace ps::eval {

/// The three histograms of one masked region (each block sums to 1, or is all 0 when the region
/// has no pixel that defines it: e.g. the spectrum of a constant region).
struct TextureHistograms {
  std::vector<std::vector<double>> lbp;  ///< one histogram of 10 bins per radius (1, 2, 4)
  std::vector<double> spectrum;          ///< 6 radial x 4 orientation bins
  std::vector<double> contrast;          ///< 16 bins
  int pixels = 0;                        ///< masked pixels described
};

struct TextureDistance {
  double total = 0;     ///< mean of the three blocks, in [0, 1]
  double lbp = 0;       ///< mean over radii of the LBP chi-square
  double spectrum = 0;  ///< chi-square of the spectrum fractions
  double contrast = 0;  ///< chi-square of the normalised-luminance histograms
};

/// The histograms of the region mask != 0 of `image`.
/// @param image CV_32FC3 linear RGB (any exposure; negative values are treated as 0)
/// @param mask  CV_8UC1, same size; at least one non-zero pixel
/// Throws ps::Exception for an empty mask, a size or type mismatch. Finite for any input
/// (black, saturated, one-pixel regions included).
TextureHistograms textureHistograms(const cv::Mat& image, const cv::Mat& mask);

/// chi2 as above between two histograms of the same length.
double chiSquare(const std::vector<double>& a, const std::vector<double>& b);

/// The distance between two described regions.
TextureDistance textureDistance(const TextureHistograms& a, const TextureHistograms& b);

/// The distance between region maskA of imageA and region maskB of imageB (the regions may have
/// different sizes and shapes; the images different sizes).
TextureDistance textureDistance(const cv::Mat& imageA, const cv::Mat& maskA, const cv::Mat& imageB,
                                const cv::Mat& maskB);

}  // namespace ps::eval

// Rotation-invariant structure statistics of a masked region, for the kNN key (paper section 3.2:
// graph selection). They complement computeTextureKey (orientation-pooled Gabor band contrast)
// with what tells tiles, planks, bricks and stone apart: the symmetry of the edges, how sparse
// the edges are, periodicity, and how colour varies with brightness.
//
// Every entry is invariant to a positive per-channel scale of the image (lighting color and
// level): luminance enters only as log(L) less its median, colour only as log(R / G) and
// log(B / G) less their medians. Every entry is invariant to a rotation of the region (up to
// resampling): orientations enter only through the magnitudes of circular harmonics, distances
// only through ring averages.
//
// Layout (S = gradientSigmas.size(), R = ringEdges.size() - 1):
//   per sigma s (4 entries): |h2|, |h4|, |h6|: magnitudes of the 2nd, 4th and 6th circular
//     harmonics of the gradient direction phi of log L (blurred by sigma), weighted by |grad|:
//     |sum w exp(i n phi)| / sum w, in [0, 1]. Parallel lines (planks, stripes) raise all three,
//     a square grid (tiles, checker, brick courses) h4 alone, a hexagonal one h6 alone, an
//     isotropic texture none. Then log(E[|g|^2] / E[|g|]^2): edge sparsity (grout lines: high;
//     dense grain: low).
//   per ring r (2 entries): mean and maximum over the ring of the normalized autocorrelation of
//     log L at distances in [ringEdges[r], ringEdges[r+1]) pixels: the correlation length, and
//     periodic lattices (a maximum well above the mean).
//   colour (6 entries): slopes of a = log(R/G) and b = log(B/G) against log L (cov / var: darker
//     grain more saturated), log(std a + floor), log(std b + floor), and the same of a and b
//     blurred by 3 pixels (chroma that varies at coarse scale: blotches, planks of two tones).
//
//   std::vector<float> s = ps::computeStructureKey(photo, partMask);
#pragma once

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace ps {

struct TextureStructureOptions {
  std::vector<float> gradientSigmas = {1.0f, 2.0f, 4.0f};  ///< pixels
  /// Ring edges of the autocorrelation (pixels), increasing, first >= 1.
  std::vector<float> ringEdges = {1.0f, 2.0f, 3.0f, 4.5f, 6.5f, 9.5f, 13.5f, 19.0f, 27.0f, 38.0f};
  /// Regions larger than this (pixels, larger side) are halved (area) for the autocorrelation,
  /// radii scaled accordingly (keeps the DFTs small).
  int maxCorrelationSize = 200;
  float logFloor = 1e-3f;
  bool IsValid(std::string* error) const;
};

/// Number of entries: 4 * gradientSigmas + 2 * rings + 6.
int structureKeyLength(const TextureStructureOptions& options);

/// Structure statistics of the masked region (layout above).
/// @param image CV_32FC3 linear RGB, non-negative, finite
/// @param mask  CV_8UC1, same size, non-empty (an empty mask throws ps::Exception)
std::vector<float> computeStructureKey(const cv::Mat& image, const cv::Mat& mask,
                                       const TextureStructureOptions& options = {});

}  // namespace ps

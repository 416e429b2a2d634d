// Typical local contrast of a masked region: how much fine structure a region shows *almost
// everywhere*, as opposed to a few strong edges; and its spread of colours (chromaSpread). Model
// selection uses it (select/synthesis.hpp): "texture only where the photo shows one".
//
// The texture loss matches means of subband energies over the part (texture_loss.hpp), and a
// mean is dominated by the strongest responses: a plain wall with a picture frame, a shelf and a
// box edge in its mask has the mean energy of a textured wall, and a graph that spreads that
// energy everywhere (tiles, blotches) lowers the loss while looking nothing like the photo. The
// median of the local contrast is robust to those few edges: on a plain wall it is the plaster's
// (and the noise's) contrast, on a tiled or planked floor it is the pattern's.
//
// Local contrast at a pixel: the standard deviation of the luminance in the (2r+1)^2 window
// around it over the window's mean (a coefficient of variation: independent of the light's level,
// and of smooth shading, which is nearly constant over a window). Only pixels whose whole window
// lies in the mask count (no contrast from the mask's border); where the mean is below
// `darkFloor` x the region's mean luminance, the floor replaces it (black pixels give no
// unbounded ratios).
//
//   ps::LocalContrast c = ps::typicalLocalContrast(photo, partMask);
//   if (c.pixels >= 50) ... c.median ...
#pragma once

#include <opencv2/core.hpp>

namespace ps {

struct LocalContrastOptions {
  int radius = 2;           ///< window (2 radius + 1)^2 pixels
  float darkFloor = 0.05f;  ///< the window mean's floor, a fraction of the region's mean luminance
  /// Structure `scale` times coarser: the luminance is first averaged over scale x scale cells
  /// (a cell counts when all its pixels are in the mask), then the window runs over the cells.
  /// Fine grain (sand, noise) averages away at scale 2; blotches, grout and grain lines stay.
  int scale = 1;
};

struct LocalContrast {
  double median = 0;  ///< median over the counted pixels (0 when none)
  double q25 = 0, q75 = 0;
  int pixels = 0;     ///< pixels whose whole window lies in the mask
};

/// Typical local contrast of `image` over `mask` (see above).
/// @param image CV_32FC3 linear RGB (negative and non-finite values read as 0)
/// @param mask  CV_8UC1 of the same size; may be empty or too thin (then pixels = 0)
LocalContrast typicalLocalContrast(const cv::Mat& image, const cv::Mat& mask,
                                   const LocalContrastOptions& options = {});

/// How many colours a region holds, whatever the light's colour: the spread of its pixels'
/// chromaticity. A white chair with a red price tag has almost none, encaustic tiles in blue and
/// orange a lot, and a light of another colour or level moves every pixel's log chromaticity by
/// the same amount, which a spread does not see. Per pixel c = (log(R / G), log(B / G)) (each
/// channel plus a hundredth of the region's median luminance, so dark pixels' noise stays
/// bounded); pixels below `darkFloor` x that median, or negative or non-finite, do not count
/// (a clipped white pixel reads neutral, which adds no spread). The spread is the length of the
/// vector of the two coordinates' 10-90 percentile ranges.
struct ChromaSpread {
  double spread = 0;  ///< 0 when no pixel counts
  int pixels = 0;     ///< pixels counted
};
ChromaSpread chromaSpread(const cv::Mat& image, const cv::Mat& mask, float darkFloor = 0.1f);

/// Which colours a region holds, as a set: a spread counts colours but not which ones, so a
/// photo whose spread comes from one hue (a white chair with red price tags, the floor showing
/// between its legs) lets through a render whose spread is another (teal grout). Each pixel's
/// c (as chromaSpread: log(R / G), log(B / G), the same dark floor) is taken relative to the
/// region's median c (a light's colour, and a fit's error in the mean colour, move every pixel
/// alike); the gamut is the set of `cell`-wide bins that hold at least two of the photo's pixels
/// (a lone noisy pixel is no colour the photo shows), grown by one bin each way.
struct ChromaGamut {
  double cell = 0.05;         ///< bin width in log-chromaticity (5 % in a channel ratio)
  std::vector<int64_t> bins;  ///< the gamut's bins, sorted (x * 2^32 + y, offset)
  int pixels = 0;             ///< pixels counted
  bool contains(double rg, double bg) const;
};
ChromaGamut chromaGamut(const cv::Mat& image, const cv::Mat& mask, float darkFloor = 0.1f,
                        double cell = 0.05);

/// The fraction of `image`'s counted pixels over `mask` whose chromaticity, relative to their own
/// median, lies outside `gamut`: the share of a render in colours the photo does not show. 0 when
/// no pixel counts or the gamut is empty (nothing to judge by).
double chromaOutside(const ChromaGamut& gamut, const cv::Mat& image, const cv::Mat& mask,
                     float darkFloor = 0.1f);

}  // namespace ps

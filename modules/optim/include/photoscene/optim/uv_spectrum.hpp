// The UV scale and rotation of a periodic material, read from the photo's spectrum
// (Fourier-Mellin).
//
// The texture statistics of the fit's loss pool over the whole part: they tell periods apart only
// to about an octave, and with the graph's default parameters (faint plank gaps, say) a wrong
// period can match the photo's statistics best; the fit then adapts the parameters to that period.
// Where a pattern repeats, the spectrum is sharper evidence: a graph's spectral peaks sit at
// frequencies set by its discrete structure (8 plank rows, 36 growth rings per uv unit), not by
// its continuous parameters, and the photo, unwarped into the part's uv space, shows the same peaks
// moved by the unknown similarity. In log-polar coordinates of the magnitude spectra that
// similarity is a translation (log-scale along the radius, rotation along the angle), found by
// correlation (the Fourier-Mellin registration of Reddy & Chatterji 1996, with a plain rather than
// a phase correlation). The magnitude spectrum is symmetric, so the rotation
// is found modulo 180 degrees.
//
//   ps::UvSpectrumEstimate e = ps::estimateUvBySpectrum(geo, photo, shading, mapLuminance);
//   if (e.ok) { /* e.logScale, e.rotation (mod pi), e.response */ }
#pragma once

#include <opencv2/core.hpp>

#include "photoscene/render/render_layer.hpp"

namespace ps {

struct UvSpectrumOptions {
  int maxRaster = 256;     ///< the uv raster's side is at most this (cells grow to fit)
  int logPolarSize = 256;  ///< log-polar images are logPolarSize x logPolarSize
  /// normalized correlation peak below this: not periodic enough (ok false). Measured: 0.08-0.12
  /// for noise, 0.24-0.29 for the synthetic wood and checker photos, 0.38-0.43 for clean rasters.
  double minResponse = 0.18;
};

struct UvSpectrumEstimate {
  bool ok = false;
  float rotation = 0;   ///< radians, in [0, pi): the UvParams rotation modulo pi
  float logScale = 0;   ///< UvParams logScale
  double response = 0;  ///< normalized correlation peak (-1..1): how clearly the spectra align
};

/// Low level: `photo` (weighted by `weight`, CV_32FC1 in [0, 1], 0 = no data) shows the pattern of
/// `graph` (the pattern at logScale 0, rotation 0 over whole periods, so that it needs no window)
/// at the returned scale and rotation. All CV_32FC1, square, one size; graphCellRatio = the graph
/// raster's cell over the photo raster's (in uv units).
UvSpectrumEstimate estimateSimilarityBySpectrum(const cv::Mat& photo, const cv::Mat& weight,
                                                const cv::Mat& graph, double graphCellRatio = 1.0,
                                                const UvSpectrumOptions& options = {});

/// The part's photo unwarped into its uv space (luminance divided by `shading`'s, the layer's
/// render of a white material; empty = no division) against the graph's luminance map
/// `mapLuminance` (CV_32FC1, N x N, one uv period). ok is false when the part is too small, its
/// footprints are degenerate or the spectra do not align clearly.
UvSpectrumEstimate estimateUvBySpectrum(const PartGeometry& geometry, const cv::Mat& photo,
                                        const cv::Mat& shading, const cv::Mat& mapLuminance,
                                        const UvSpectrumOptions& options = {});

}  // namespace ps

// Denoiser guided by the G-buffers: an edge-avoiding a-trous wavelet filter (Dammertz et al.
// 2010, with the SVGF weights of Schied et al. 2017) on the albedo-demodulated image.
//
//   irradiance = noisy / max(albedo, eps)                 (per channel: textures leave the signal)
//   5 levels of a 5x5 B3-spline a-trous filter, step 1, 2, 4, 8, 16 px, each tap weighted by
//     w = h(dx) h(dy) * max(0, n_p . n_q)^sigmaNormal                      (normal)
//           * exp(-|z_p - z_q| / (sigmaDepth |grad z_p| |offset| + 1e-3 z_p)) (depth plane)
//           * exp(-|l_p - l_q| / (sigmaLuminance sqrt(g3x3(var_p)) + 1e-6))   (luminance)
//     the luminance variance carried from level to level as sum w^2 var / (sum w)^2
//   denoised = filtered irradiance * max(albedo, eps)
//
// Pixels with depth 0 (the ray escaped: environment) are returned as they are and are never
// taps of a surface pixel. The filter is deterministic: each output pixel is a fixed sum, rows
// are split over threads (ps::parallelFor), so any thread count gives the same bits.
//
// Only for images people look at (previews, `photoscene render --denoise`, export and
// evaluation renders): never denoise what the light solve or the material fit read (it would
// bias their least squares with the filter's blur).
//
//   ps::DenoiseGuides g;
//   cv::Mat noisy = tracer.render(cam, opt, nullptr, &g);   // guides from the render's samples
//   cv::Mat clean = ps::denoise(g, noisy);
#pragma once

#include <opencv2/core.hpp>

#include "photoscene/raytrace/gbuffer.hpp"
#include "photoscene/raytrace/path_tracer.hpp"

namespace ps {

// DenoiseGuides (path_tracer.hpp): per-pixel albedo, normal, depth and variance.

struct DenoiseOptions {
  int levels = 5;               ///< a-trous levels (step 2^i px, i < levels): 5 reaches +-62 px
  float sigmaLuminance = 4.0f;  ///< luminance edge-stop, in standard deviations
  float sigmaNormal = 128.0f;   ///< exponent of the normal edge-stop
  float sigmaDepth = 1.0f;      ///< depth edge-stop, in multiples of the local depth gradient
  float albedoEpsilon = 0.01f;  ///< demodulation divides by max(albedo, albedoEpsilon)
  bool IsValid(std::string* error) const;
};

/// Denoises `noisy` (CV_32FC3 linear RGB, >= 0, finite; negative or non-finite values are read
/// as 0) with the guides. Returns CV_32FC3 of the same size, finite, >= 0. Throws
/// std::invalid_argument on mismatched sizes or types or invalid options.
cv::Mat denoise(const DenoiseGuides& guides, const cv::Mat& noisy,
                const DenoiseOptions& options = {});

/// The guides of a G-buffer rendered from `tracer` (use GBufferOptions::passWindows = true, so
/// that windows show what the path tracer sees through them): albedo = diffuse colour + F0 of
/// the first hit's material at its uv (clamped to [0, 1]), the shading normal, the depth.
/// `variance` is left empty.
DenoiseGuides denoiseGuides(const PathTracer& tracer, const GBuffer& gbuffer);

/// Luminance variance of the mean of two independent half renders a and b (CV_32FC3, each of
/// half the samples): ((lum(a) - lum(b)) / 2)^2, the one-pair estimate, blurred 3x3.
cv::Mat varianceFromHalves(const cv::Mat& a, const cv::Mat& b);

}  // namespace ps

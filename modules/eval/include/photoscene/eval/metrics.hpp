// Image similarity metrics: how close a render of the twin is to a photo.
//
// Every number is computed in a stated color space:
//   ColorSpace::Srgb255  values v = 255 * srgbEncode(clamp(linear, 0, 1)), unquantized floats:
//                        what a viewer sees on an 8-bit display (the paper's setting)
//   ColorSpace::Linear   the linear values as they are (scene-referred, may exceed 1)
//
// Inputs are cv::Mat CV_32FC3 linear RGB of the same size; masks CV_8UC1 (non-zero = inside).
//
//   RMSE  sqrt(mean over masked pixels and the 3 channels of (a - b)^2)  (the paper's per-part
//         error over the part's aligned mask)
//   PSNR  10 log10(peak^2 / MSE), peak = 255 (Srgb255) or 1 (Linear); +inf for identical images
//   SSIM  Wang et al. 2004 (Gaussian window 11 x 11, sigma 1.5, K1 = 0.01, K2 = 0.03, dynamic
//         range 255 or 1), OpenCV's quality module, mean over pixels and channels; 1 = identical
//   GMSD  gradient magnitude similarity deviation (Xue et al. 2014): luma, 2x2 average
//         downsampling, Prewitt gradients, c = 170 (range 255; scaled for Linear), the standard
//         deviation of the similarity map; 0 = identical, larger is worse. A gradient-based
//         perceptual measure in place of LPIPS, whose network weights cannot be had here.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace ps::eval {

enum class ColorSpace { Srgb255, Linear };

std::string toString(ColorSpace space);

/// Converts a linear CV_32FC3 image into the metric's color space (CV_32FC3).
cv::Mat toMetricSpace(const cv::Mat& linearRgb, ColorSpace space);

/// RMSE over the pixels where mask != 0 (all pixels when mask is empty). NaN when the mask is
/// empty of pixels (no value: callers report "no pixels", never a number).
double rmse(const cv::Mat& a, const cv::Mat& b, ColorSpace space, const cv::Mat& mask = cv::Mat());
double psnr(const cv::Mat& a, const cv::Mat& b, ColorSpace space, const cv::Mat& mask = cv::Mat());
double ssim(const cv::Mat& a, const cv::Mat& b, ColorSpace space);
double gmsd(const cv::Mat& a, const cv::Mat& b, ColorSpace space);

struct ImageMetrics {
  ColorSpace space = ColorSpace::Srgb255;
  double rmse = 0, psnr = 0, ssim = 0, gmsd = 0;
};

/// All four metrics of a render against a photo over the whole image.
ImageMetrics compareImages(const cv::Mat& render, const cv::Mat& photo, ColorSpace space);

}  // namespace ps::eval

// The image convention of photoscene.
//
//   color images  cv::Mat CV_32FC3, linear RGB (R first: not OpenCV's BGR), scene-referred
//                 (values may exceed 1), row 0 at the top, pixel (x, y) centered at (x, y)
//   scalar maps   cv::Mat CV_32FC1 (roughness, depth, coverage, ...)
//   masks         cv::Mat CV_8UC1, 0 = outside, 255 = inside (any non-zero is inside)
//   labels        cv::Mat CV_32SC1, 0 = unlabeled
//
// sRGB <-> linear uses the exact IEC 61966-2-1 piecewise curve (not a 2.2 gamma).
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace ps {

/// Exact sRGB decode of one value in [0, 1] (values outside are clamped first).
float srgbToLinear(float encoded);
/// Exact sRGB encode of one linear value; clamps to [0, 1].
float linearToSrgb(float linear);

/// Decodes an sRGB image to linear float.
/// @param src CV_8UC(n) (scaled by 1/255), CV_16UC(n) (1/65535) or CV_32FC(n) in [0, 1]
/// @return CV_32FC(n), linear, same size
cv::Mat srgbToLinear(const cv::Mat& src);
/// Encodes a linear image to sRGB (clamped to [0, 1]).
/// @param src   CV_32FC(n), linear
/// @param depth CV_8U, CV_16U (rounded to nearest) or CV_32F (encoded values in [0, 1])
cv::Mat linearToSrgb(const cv::Mat& src, int depth = CV_8U);

/// Human-readable name of a cv::Mat type ("CV_32FC3").
std::string typeName(int type);

/// Throws ps::Exception naming `what` unless `m` is non-empty and of type `type`.
void checkImage(const cv::Mat& m, int type, const char* what);
/// As checkImage and also requires size `size`.
void checkImage(const cv::Mat& m, int type, cv::Size size, const char* what);

/// True when every value of a float image is finite.
bool allFinite(const cv::Mat& m);

}  // namespace ps

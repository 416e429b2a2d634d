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

#include "photoscene/core/math.hpp"

#include <cmath>
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

/// Bilinear, periodic (tiling) sample of a CV_32FC3 map at texture coordinate (tu, tv): u = 0 at
/// the left edge, v = 0 at the bottom (row 0 = top), one period per unit. Not checked: `map` must
/// be a non-empty CV_32FC3 (a hot inner-loop lookup, hence inline).
inline cv::Vec3f samplePeriodic(const cv::Mat& map, float tu, float tv) {
  const int n = map.cols, m = map.rows;
  const float x = tu * n - 0.5f, y = (1.0f - tv) * m - 0.5f;
  const float fx0 = std::floor(x), fy0 = std::floor(y);
  const float fx = x - fx0, fy = y - fy0;
  // one integer division per axis, the next texel wrapped by a comparison (the same texels as
  // two divisions per index; the exemplar bank's patch renders call this about 10^9 times)
  const int x0 = wrapIndex(static_cast<int>(fx0), n), x1 = x0 + 1 == n ? 0 : x0 + 1;
  const int y0 = wrapIndex(static_cast<int>(fy0), m), y1 = y0 + 1 == m ? 0 : y0 + 1;
  const cv::Vec3f* r0 = map.ptr<cv::Vec3f>(y0);
  const cv::Vec3f* r1 = map.ptr<cv::Vec3f>(y1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x1]);
}

}  // namespace ps

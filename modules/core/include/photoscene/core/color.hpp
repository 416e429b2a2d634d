// Luminance of linear RGB: Y = 0.2126 R + 0.7152 G + 0.0722 B (the Rec. 709 / sRGB primaries'
// weights), the one definition every module uses (light power, texture statistics, denoising,
// exposure pins). The float and double forms use the weights written in their own precision
// (0.2126f, not float(0.2126)), so each sums exactly as the expression it replaces.
#pragma once

#include <opencv2/core/matx.hpp>

#include "photoscene/core/math.hpp"

namespace ps {

/// Rec. 709 luminance weights (R, G, B), in float and in double.
inline constexpr float kLuminanceWeightsF[3] = {0.2126f, 0.7152f, 0.0722f};
inline constexpr double kLuminanceWeights[3] = {0.2126, 0.7152, 0.0722};

/// Y of a linear-RGB value: 0.2126 r + 0.7152 g + 0.0722 b, summed left to right.
inline float luminance(float r, float g, float b) {
  return kLuminanceWeightsF[0] * r + kLuminanceWeightsF[1] * g + kLuminanceWeightsF[2] * b;
}
inline double luminance(double r, double g, double b) {
  return kLuminanceWeights[0] * r + kLuminanceWeights[1] * g + kLuminanceWeights[2] * b;
}
inline float luminance(const Vec3f& c) {
  return luminance(c.x(), c.y(), c.z());
}
inline double luminance(const Vec3d& c) {
  return luminance(c.x(), c.y(), c.z());
}
inline float luminance(const cv::Vec3f& c) {
  return luminance(c[0], c[1], c[2]);
}

}  // namespace ps

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "photoscene/core.hpp"
#include "photoscene/eval.hpp"

namespace ps::eval {
namespace {

/// A periodic "brick" texture (period 32 x 16 px, mortar lines, per-brick tone, fine grain),
/// `size` x `size` pixels starting at texel (ox, oy): the same texture at another offset.
cv::Mat bricks(int size, int ox, int oy, float noise = 0.0f, uint64_t noiseSeed = 1) {
  Rng grain(7), rng(noiseSeed);
  cv::Mat tile(64, 64, CV_32FC1);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) tile.at<float>(y, x) = 0.85f + 0.3f * grain.uniform();
  cv::Mat img(size, size, CV_32FC3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const int u = x + ox, v = y + oy;
      const int row = v / 16;
      const int col = (u + (row % 2) * 16) / 32;
      const bool mortar = v % 16 < 2 || (u + (row % 2) * 16) % 32 < 2;
      const float tone = 0.35f + 0.1f * static_cast<float>((row * 7 + col * 3) % 5) / 4.0f;
      float l = mortar ? 0.7f : tone * tile.at<float>(v % 64, u % 64);
      l *= 1.0f + noise * rng.normal();
      img.at<cv::Vec3f>(y, x) = cv::Vec3f(l * 1.1f, l, l * 0.8f);
    }
  return img;
}

/// Vertical stripes of period 12 px (or horizontal when `horizontal`), with fine grain.
cv::Mat stripes(int size, bool horizontal) {
  Rng rng(3);
  cv::Mat img(size, size, CV_32FC3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const int t = horizontal ? y : x;
      const float l =
          0.4f + 0.2f * std::sin(2.0f * 3.14159265f * t / 12.0f) + 0.02f * rng.uniform();
      img.at<cv::Vec3f>(y, x) = cv::Vec3f(l, l, l);
    }
  return img;
}

cv::Mat full(int size) {
  return cv::Mat(size, size, CV_8UC1, cv::Scalar(255));
}

cv::Mat disk(int size) {
  cv::Mat m = cv::Mat::zeros(size, size, CV_8UC1);
  cv::circle(m, {size / 2, size / 2}, size / 2 - 2, cv::Scalar(255), cv::FILLED);
  return m;
}

TEST(Eval_TextureDistance, identical_regions_are_at_distance_zero) {
  const cv::Mat a = bricks(96, 0, 0);
  const TextureDistance d = textureDistance(a, full(96), a, full(96));
  EXPECT_EQ(d.total, 0.0);
  EXPECT_EQ(d.lbp, 0.0);
  EXPECT_EQ(d.spectrum, 0.0);
  EXPECT_EQ(d.contrast, 0.0);
}

TEST(Eval_TextureDistance, same_texture_at_another_offset_and_noise_is_near_other_textures_far) {
  // the photo and a re-render of the right material: not pixel-aligned, independent noise
  const cv::Mat photo = bricks(128, 0, 0, 0.05f, 1);
  const cv::Mat shifted = bricks(128, 21, 37, 0.05f, 2);
  const double same = textureDistance(photo, full(128), shifted, full(128)).total;
  const double vsStripes = textureDistance(photo, full(128), stripes(128, false), full(128)).total;
  cv::Mat flat(128, 128, CV_32FC3, cv::mean(photo));
  const double vsFlat = textureDistance(photo, full(128), flat, full(128)).total;
  EXPECT_LT(same, 0.05);
  EXPECT_GT(vsStripes, 6 * same);
  EXPECT_GT(vsFlat, 6 * same);
  // shapes and sizes of the regions may differ
  const double otherShape =
      textureDistance(photo, full(128), bricks(160, 5, 3, 0.05f, 3), disk(160)).total;
  EXPECT_LT(otherShape, 0.1);
  EXPECT_GT(vsStripes, 3 * otherShape);
}

TEST(Eval_TextureDistance, sees_orientation_and_contrast) {
  const cv::Mat v = stripes(96, false), h = stripes(96, true);
  const cv::Mat big = stripes(128, false);
  const cv::Mat vShifted = big(cv::Rect(5, 9, 96, 96)).clone();
  const double shift = textureDistance(v, full(96), vShifted, full(96)).total;
  const TextureDistance turned = textureDistance(v, full(96), h, full(96));
  EXPECT_GT(turned.spectrum, 0.5);
  EXPECT_GT(turned.total, 4 * shift);
  // half the contrast about the same mean: the contrast block sees it
  const cv::Scalar m = cv::mean(v);
  cv::Mat low = 0.5 * v + 0.5 * cv::Mat(v.size(), CV_32FC3, m);
  const TextureDistance lowC = textureDistance(v, full(96), low, full(96));
  EXPECT_GT(lowC.contrast, 0.3);
  EXPECT_GT(lowC.total, 4 * shift);
}

TEST(Eval_TextureDistance, invariant_to_a_global_brightness_scale) {
  const cv::Mat a = bricks(96, 0, 0, 0.03f);
  const cv::Mat dark = a * 0.2, bright = a * 7.0;
  EXPECT_LT(textureDistance(a, full(96), dark, full(96)).total, 1e-3);
  EXPECT_LT(textureDistance(a, full(96), bright, full(96)).total, 1e-3);
}

TEST(Eval_TextureDistance, chi_square_is_symmetric_and_in_unit_range) {
  EXPECT_DOUBLE_EQ(chiSquare({1, 0}, {0, 1}), 1.0);
  EXPECT_DOUBLE_EQ(chiSquare({0.5, 0.5}, {0.5, 0.5}), 0.0);
  EXPECT_DOUBLE_EQ(chiSquare({0, 0}, {0, 0}), 0.0);
  EXPECT_DOUBLE_EQ(chiSquare({0.2, 0.8}, {0.6, 0.4}), chiSquare({0.6, 0.4}, {0.2, 0.8}));
  EXPECT_THROW(chiSquare({1}, {0.5, 0.5}), ps::Exception);
  const cv::Mat a = bricks(64, 0, 0), b = stripes(64, true);
  const TextureDistance d = textureDistance(a, full(64), b, full(64));
  for (double x : {d.total, d.lbp, d.spectrum, d.contrast}) {
    EXPECT_GE(x, 0.0);
    EXPECT_LE(x, 1.0);
  }
  EXPECT_DOUBLE_EQ(d.total, textureDistance(b, full(64), a, full(64)).total);
}

TEST(Eval_TextureDistance, degenerate_regions_give_finite_values_or_a_clear_error) {
  const cv::Mat a = bricks(48, 0, 0);
  const cv::Mat none = cv::Mat::zeros(48, 48, CV_8UC1);
  EXPECT_THROW(textureHistograms(a, none), ps::Exception);
  EXPECT_THROW(textureHistograms(a, cv::Mat(10, 10, CV_8UC1, cv::Scalar(255))), ps::Exception);
  EXPECT_THROW(textureHistograms(cv::Mat(48, 48, CV_32FC1, cv::Scalar(0)), full(48)),
               ps::Exception);
  cv::Mat onePixel = none.clone(), corner = none.clone();
  onePixel.at<uint8_t>(20, 20) = 255;
  corner.at<uint8_t>(0, 0) = 255;  // no LBP circle fits: that block is all 0
  const cv::Mat black = cv::Mat::zeros(48, 48, CV_32FC3);
  const cv::Mat saturated(48, 48, CV_32FC3, cv::Scalar(1e30, 1e30, 1e30));
  cv::Mat withNan = a.clone();
  withNan.at<cv::Vec3f>(5, 5) = cv::Vec3f(std::numeric_limits<float>::quiet_NaN(), 0, 0);
  withNan.at<cv::Vec3f>(6, 6) = cv::Vec3f(std::numeric_limits<float>::infinity(), -1, 0);
  for (const cv::Mat& img : {a, black, saturated, withNan})
    for (const cv::Mat& m : {full(48), onePixel, corner, disk(48)}) {
      const TextureDistance d = textureDistance(img, m, a, full(48));
      for (double x : {d.total, d.lbp, d.spectrum, d.contrast}) {
        EXPECT_TRUE(std::isfinite(x));
        EXPECT_GE(x, 0.0);
        EXPECT_LE(x, 1.0);
      }
    }
  // constant regions (black or gray) look alike
  const cv::Mat gray(48, 48, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5));
  EXPECT_EQ(textureDistance(black, full(48), gray, full(48)).total, 0.0);
}

}  // namespace
}  // namespace ps::eval

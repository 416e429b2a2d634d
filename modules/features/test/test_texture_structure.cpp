#include "photoscene/core.hpp"
#include "photoscene/features.hpp"
#include "texture_fixtures.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cmath>
#include <vector>

namespace ps {
namespace {

using namespace test;  // texture_fixtures.hpp

TEST(Features_Structure, length_and_invariance_to_light_color_and_level) {
  const TextureStructureOptions o;
  EXPECT_EQ(structureKeyLength(o), 4 * 3 + 2 * 9 + 6);
  const cv::Size size(96, 96);
  const cv::Mat mask = diskMask(size, {48, 48}, 44);
  for (const cv::Mat& img : {stripes(size, 9, 30), checker(size, 8), noise(size, 2.0, 3)}) {
    const std::vector<float> k0 = computeStructureKey(img, mask);
    ASSERT_EQ(static_cast<int>(k0.size()), structureKeyLength(o));
    for (float v : k0) EXPECT_TRUE(std::isfinite(v));
    const std::vector<float> k1 = computeStructureKey(scaleChannels(img, {2.5f, 0.4f, 1.3f}), mask);
    EXPECT_LT(descriptorDistance(k0, k1), 1e-3);
  }
}

TEST(Features_Structure, edge_symmetry_tells_lines_grids_and_noise_apart) {
  // h2 / h4 at sigma 1: parallel stripes both high, a square checker h4 only, noise neither
  const cv::Size size(96, 96);
  const cv::Mat mask(size, CV_8UC1, cv::Scalar(255));
  const std::vector<float> s = computeStructureKey(stripes(size, 8, 30), mask);
  const std::vector<float> c = computeStructureKey(checker(size, 8), mask);
  const std::vector<float> n = computeStructureKey(noise(size, 1.5, 5), mask);
  EXPECT_GT(s[0], 0.8f);
  EXPECT_GT(s[1], 0.6f);
  EXPECT_LT(c[0], 0.2f);
  EXPECT_GT(c[1], 0.6f);
  EXPECT_LT(n[0], 0.2f);
  EXPECT_LT(n[1], 0.2f);
  // rotating the region by 90 degrees leaves the key unchanged up to resampling
  cv::Mat rotated;
  cv::rotate(stripes(size, 8, 30), rotated, cv::ROTATE_90_CLOCKWISE);
  EXPECT_LT(descriptorDistance(s, computeStructureKey(rotated, mask)), 1e-3);
  // a periodic checker correlates with itself at its period (2 cells along a diagonal, a cell
  // apart along an axis: -1), so its ring maxima exceed those of blurred noise at long range
  const int rings = static_cast<int>(TextureStructureOptions{}.ringEdges.size()) - 1;
  float checkerMax = -1, noiseMax = -1;
  for (int r = rings / 2; r < rings - 1; ++r) {
    checkerMax = std::max(checkerMax, c[12 + 2 * r + 1]);
    noiseMax = std::max(noiseMax, n[12 + 2 * r + 1]);
  }
  EXPECT_GT(checkerMax, 0.5f);
  EXPECT_LT(noiseMax, 0.5f);
}

TEST(Features_Structure, small_and_odd_masks_give_finite_keys) {
  const cv::Size size(64, 48);
  const cv::Mat img = noise(size, 1.0, 9);
  cv::Mat tiny = cv::Mat::zeros(size, CV_8UC1);
  tiny.at<uint8_t>(10, 10) = 255;
  tiny.at<uint8_t>(10, 11) = 255;
  for (const cv::Mat& m : {tiny, diskMask(size, {32, 24}, 6)}) {
    const std::vector<float> k = computeStructureKey(img, m);
    for (float v : k) EXPECT_TRUE(std::isfinite(v));
  }
  EXPECT_THROW(computeStructureKey(img, cv::Mat::zeros(size, CV_8UC1)), Exception);
}

}  // namespace
}  // namespace ps

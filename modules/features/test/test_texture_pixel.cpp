// Pixel-scale structure (texture_pixel.hpp): it tells a white grain from a correlated one at the
// same contrast, ignores the light's level, its gradient matches finite differences, and black,
// saturated and tiny images give finite values.
#include "photoscene/core/error.hpp"
#include "photoscene/features.hpp"
#include "texture_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace ps {
namespace {

using test::noise;

const cv::Size kPixelSize(64, 48);

bool finitePixelStructure(const PixelStructure& s) {
  bool ok = std::isfinite(s.contrast) && std::isfinite(s.mean);
  for (double c : s.correlation) ok = ok && std::isfinite(c);
  return ok;
}

std::vector<cv::Point> somePixels(int count, uint64_t seed) {
  return test::randomPixels(cv::Mat(kPixelSize, CV_8UC1, cv::Scalar(255)), true, count, seed);
}

TEST(Features_Pixel, a_correlated_grain_reads_apart_from_a_white_one_whatever_the_light) {
  const cv::Mat white = noise(kPixelSize, 0.3, 1), grain = noise(kPixelSize, 1.2, 2);
  const PixelStructure w = pixelStructure(white), g = pixelStructure(grain);
  // white noise: the residual of neighbours is anticorrelated (the 3 x 3 mean shares them);
  // a grain correlated over a pixel or more keeps neighbours alike
  EXPECT_LT(w.correlation[0], 0.0);
  EXPECT_GT(g.correlation[0], w.correlation[0] + 0.3);
  EXPECT_GT(g.correlation[1], w.correlation[1] + 0.3);
  // the smoother grain has less energy left at the pixel scale
  EXPECT_LT(g.contrast, 0.5 * w.contrast);
  // light level and colour cancel
  const PixelStructure dim = pixelStructure(test::scaleChannels(grain, {0.1f, 0.1f, 0.1f}));
  EXPECT_NEAR(dim.contrast, g.contrast, 1e-4);
  for (int d = 0; d < PixelStructure::kLags; ++d)
    EXPECT_NEAR(dim.correlation[d], g.correlation[d], 1e-5);
  EXPECT_EQ(g.pixels, (kPixelSize.width - 6) * (kPixelSize.height - 6));
  std::printf("white: contrast %.4f, lag (1, 0) %.3f; grain: %.4f, %.3f\n", w.contrast,
              w.correlation[0], g.contrast, g.correlation[0]);
  // the loss is 0 at the target (up to the loss's regulariser) and grows away from it
  EXPECT_NEAR(pixelStructureLoss(grain, g, 1.0), 0.0, 1e-6);
  EXPECT_GT(pixelStructureLoss(white, g, 1.0), 0.05);
}

TEST(Features_Pixel, gradient_matches_finite_differences) {
  const PixelStructure target = pixelStructure(noise(kPixelSize, 1.0, 5));
  for (const double blur : {0.3, 2.0}) {
    const cv::Mat render = noise(kPixelSize, blur, 7);
    const TextureLossGradientCheck c =
        checkPixelStructureGradient(render, target, 3.0, somePixels(60, 11), 1e-3);
    SCOPED_TRACE(blur);
    EXPECT_EQ(c.checked, 180);
    EXPECT_GT(c.maxNumeric, 0.0);
    EXPECT_LT(c.maxRelError, 0.02) << "max abs " << c.maxAbsError << " floor " << c.floor;
  }
  // pixels on the outer ring (no residual of their own) reach the loss through their
  // neighbours' 3 x 3 means and the mean luminance
  const cv::Mat render = noise(kPixelSize, 0.8, 9);
  const TextureLossGradientCheck ring = checkPixelStructureGradient(
      render, target, 1.0, {{0, 0}, {kPixelSize.width - 1, 5}, {3, kPixelSize.height - 1}}, 1e-3);
  EXPECT_LT(ring.maxRelError, 0.02);
}

TEST(Features_Pixel, black_saturated_flat_and_tiny_images_stay_finite) {
  const PixelStructure target = pixelStructure(noise(kPixelSize, 1.0, 5));
  const cv::Mat black = cv::Mat::zeros(kPixelSize, CV_32FC3);
  const cv::Mat flat(kPixelSize, CV_32FC3, cv::Scalar::all(0.5));
  cv::Mat saturated = noise(kPixelSize, 1.0, 3) * 40.0;
  cv::min(saturated, 1.0, saturated);  // clipped: large flat patches at 1
  for (const cv::Mat& img : std::vector<cv::Mat>{black, flat, saturated}) {
    const PixelStructure s = pixelStructure(img);
    EXPECT_TRUE(finitePixelStructure(s));
    cv::Mat grad;
    const double l = pixelStructureLoss(img, target, 1.0, &grad);
    EXPECT_TRUE(std::isfinite(l));
    EXPECT_TRUE(cv::checkRange(grad));
    // and as a target
    cv::Mat g2;
    EXPECT_TRUE(std::isfinite(pixelStructureLoss(noise(kPixelSize, 1.0, 4), s, 1.0, &g2)));
    EXPECT_TRUE(cv::checkRange(g2));
  }
  // black against black: nothing to match, no gradient
  cv::Mat gb;
  EXPECT_EQ(pixelStructureLoss(black, pixelStructure(black), 1.0, &gb), 0.0);
  EXPECT_EQ(cv::countNonZero(gb.reshape(1)), 0);
  // under 7 x 7 pixels (a one-pixel view): no statistics, no loss, no gradient
  for (const cv::Size tiny : {cv::Size(1, 1), cv::Size(6, 40), cv::Size(40, 6)}) {
    const cv::Mat img(tiny, CV_32FC3, cv::Scalar::all(0.3));
    EXPECT_EQ(pixelStructure(img).pixels, 0);
    cv::Mat g;
    EXPECT_EQ(pixelStructureLoss(img, target, 1.0, &g), 0.0);
    EXPECT_TRUE(g.empty());
  }
  // a wrong type is refused
  EXPECT_THROW(pixelStructure(cv::Mat(kPixelSize, CV_8UC3)), Exception);
}

}  // namespace
}  // namespace ps

// The texture loss's colour distribution term (TextureLossWeights::colorSliced): the sliced
// Wasserstein distance of the masked pixels' colours.
#include "photoscene/core.hpp"
#include "photoscene/features.hpp"
#include "texture_fixtures.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ps {
namespace {

using namespace test;  // texture_fixtures.hpp

TextureLossOptions slicedOnly(float weight = 1.0f) {
  TextureLossOptions o;
  TextureLossWeights& w = o.weights;
  w.colorMean = w.colorStd = w.bandMeanRe = w.bandStdRe = w.bandMeanMag = w.bandStdMag = 0.0f;
  w.colorSliced = weight;
  return o;
}

double slicedLoss(const TextureLossTarget& target, const cv::Mat& render) {
  TextureLossParams p;
  p.target = &target;
  p.render = render;
  textureLossForward(p);
  return p.slicedLoss;
}

cv::Mat randomColours(cv::Size size, uint64_t seed) {
  Rng rng(seed);
  cv::Mat out(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      for (int c = 0; c < 3; ++c) out.at<cv::Vec3f>(y, x)[c] = float(0.05 + 0.9 * rng.uniform());
  return out;
}

// The analytic gradient against central differences. The term is piecewise quadratic in a pixel's
// value (its rank among the projections changes where two pixels cross), so the check runs on a
// sparse mask of 40 pixels with a small step: no checked pixel crosses another's projection. Pixels
// outside the mask have gradient 0. Then the whole loss with the term added to the default groups,
// on a one-pixel mask (no ranks to change), checks that backward adds it to the others.
TEST(Features_TextureSliced, gradient_matches_finite_differences) {
  const cv::Size size(24, 20);
  cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
  Rng rng(4);
  while (cv::countNonZero(mask) < 40)
    mask.at<uint8_t>(int(rng.uniformInt(size.height)), int(rng.uniformInt(size.width))) = 255;
  const TextureLossTarget target(randomColours(size, 1), mask, slicedOnly());
  const cv::Mat render = randomColours(size, 2);
  std::vector<cv::Point> pixels = randomPixels(mask, true, 10, 5);
  const std::vector<cv::Point> outside = randomPixels(mask, false, 3, 6);
  pixels.insert(pixels.end(), outside.begin(), outside.end());
  const TextureLossGradientCheck r = checkTextureLossGradient(target, render, pixels, 1e-4);
  EXPECT_EQ(r.checked, 3 * 13);
  EXPECT_GT(r.maxNumeric, 1e-3);
  EXPECT_LT(r.maxRelError, 1e-2) << "max abs error " << r.maxAbsError << ", floor " << r.floor;
  cv::Mat grad;
  lossAndGradient(target, render, grad);
  for (const cv::Point& q : outside) EXPECT_EQ(grad.at<cv::Vec3f>(q), cv::Vec3f(0, 0, 0));

  TextureLossOptions both;
  both.weights.colorSliced = 2.0f;
  cv::Mat one = cv::Mat::zeros(size, CV_8UC1);
  one.at<uint8_t>(9, 11) = 255;
  const TextureLossTarget onePixel(randomColours(size, 7), one, both);
  const TextureLossGradientCheck r1 =
      checkTextureLossGradient(onePixel, randomColours(size, 8), {{11, 9}, {12, 9}}, 1e-3);
  EXPECT_LT(r1.maxRelError, 2e-2) << r1.maxAbsError;
}

// Moments per channel cannot tell a blue ornament on white from a mosaic whose red, green and blue
// are each the photo's values in the same proportions but on other pixels (purple, cyan, yellow
// and white tiles): identical colour means and standard deviations (those groups are 0), while the
// sliced term sees the joint distribution. It ignores where the colours are: the photo's own
// pixels shuffled score 0. And it is scale free like the rest of the loss (divided by nu).
TEST(Features_TextureSliced, tells_a_colour_mixture_that_moments_cannot) {
  const cv::Size size(64, 48);
  const cv::Mat mask(size, CV_8UC1, cv::Scalar(255));
  const cv::Vec3f blue(0.1f, 0.2f, 0.7f), white(0.8f, 0.8f, 0.8f);
  cv::Mat photo(size, CV_32FC3), mosaic(size, CV_32FC3), shuffled(size, CV_32FC3);
  const int n = size.area();
  for (int i = 0; i < n; ++i) {
    // 3 of every 8 pixels are ornament; the mosaic gives each channel its low value on a different
    // 3 of 8 (so each channel's marginal is the photo's)
    const int j = i % 8;
    const bool ornament = j < 3;
    photo.at<cv::Vec3f>(i / size.width, i % size.width) = ornament ? blue : white;
    cv::Vec3f m;
    m[0] = (j < 3) ? blue[0] : white[0];
    m[1] = (j >= 2 && j < 5) ? blue[1] : white[1];
    m[2] = (j >= 4 && j < 7) ? blue[2] : white[2];
    mosaic.at<cv::Vec3f>(i / size.width, i % size.width) = m;
    const int k = (i * 37 + 11) % n;  // a permutation of the pixels (37 is prime to 3072)
    shuffled.at<cv::Vec3f>(k / size.width, k % size.width) = ornament ? blue : white;
  }
  TextureLossOptions o;
  o.weights.colorSliced = 1.0f;
  const TextureLossTarget target(photo, mask, o);
  TextureLossParams p;
  p.target = &target;
  p.render = mosaic;
  textureLossForward(p);
  EXPECT_LT(p.groupLoss[0] + p.groupLoss[1], 1e-10);  // colour means and standard deviations
  EXPECT_GT(p.slicedLoss, 0.01);
  EXPECT_NEAR(slicedLoss(target, shuffled), 0.0, 1e-12);
  const TextureLossTarget target3(photo * 3.0, mask, o);
  EXPECT_NEAR(slicedLoss(target3, mosaic * 3.0) / p.slicedLoss, 1.0, 1e-4);
  // the gradient step moves the mosaic towards the photo's colours
  cv::Mat grad;
  const double l0 = lossAndGradient(TextureLossTarget(photo, mask, slicedOnly()), mosaic, grad);
  const cv::Mat stepped = mosaic - grad * (0.2 * l0 / cv::norm(grad, cv::NORM_L2SQR));
  EXPECT_LT(slicedLoss(TextureLossTarget(photo, mask, slicedOnly()), stepped), 0.9 * l0);
}

// The photo's noise widens its colour distribution; a render carries none. With photoNoiseFloor
// the target's sorted values lose the noise's variance: against a noisy plain photo the clean flat
// render's term drops by more than 10x, and the target keeps a real texture's spread.
TEST(Features_TextureSliced, noise_floor_narrows_the_photos_distribution) {
  const cv::Size size(96, 80);
  const cv::Mat mask = diskMask(size, {48, 40}, 36);
  const cv::Mat flat(size, CV_32FC3, cv::Scalar(0.4, 0.36, 0.32));
  Rng rng(3);
  cv::Mat photo = flat.clone();
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      for (int c = 0; c < 3; ++c) photo.at<cv::Vec3f>(y, x)[c] += float(0.03 * rng.normal());
  TextureLossOptions off = slicedOnly(), on = slicedOnly();
  on.photoNoiseFloor = true;
  const double lOff = slicedLoss(TextureLossTarget(photo, mask, off), flat);
  const double lOn = slicedLoss(TextureLossTarget(photo, mask, on), flat);
  EXPECT_GT(lOff, 0.0);
  EXPECT_LT(lOn, 0.1 * lOff) << lOff << " -> " << lOn;
  // a checker of 0.2 / 0.6 under the same noise: the clean checker still matches far better than
  // the flat mean colour
  const cv::Mat check = checker(size, 6);
  cv::Mat noisyCheck = check.clone();
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      for (int c = 0; c < 3; ++c) noisyCheck.at<cv::Vec3f>(y, x)[c] += float(0.03 * rng.normal());
  const TextureLossTarget t(noisyCheck, mask, on);
  const cv::Scalar mean = cv::mean(noisyCheck, mask);
  const cv::Mat flatMean(size, CV_32FC3, mean);
  EXPECT_LT(slicedLoss(t, check), 0.05 * slicedLoss(t, flatMean));
}

// No NaN or Inf from degenerate masks and extreme images.
TEST(Features_TextureSliced, stress_masks_and_images_stay_finite) {
  const cv::Size size(40, 32);
  cv::Mat onePixel = cv::Mat::zeros(size, CV_8UC1);
  onePixel.at<uint8_t>(0, 39) = 255;
  const cv::Mat full(size, CV_8UC1, cv::Scalar(255));
  const cv::Mat black = cv::Mat::zeros(size, CV_32FC3);
  const cv::Mat saturated(size, CV_32FC3, cv::Scalar(1e4, 1e4, 1e4));
  const cv::Mat tex = noise(size, 1.0, 3);
  TextureLossOptions o;
  o.weights.colorSliced = 1.0f;
  o.photoNoiseFloor = true;
  for (const cv::Mat& mask : {onePixel, full})
    for (const cv::Mat& photo : {black, saturated, tex})
      for (const cv::Mat& render : {black, saturated, tex}) {
        const TextureLossTarget target(photo, mask, o);
        cv::Mat grad;
        ASSERT_TRUE(std::isfinite(lossAndGradient(target, render, grad)));
        ASSERT_TRUE(allFinite(grad));
      }
  o.weights.colorSliced = -1.0f;
  std::string err;
  EXPECT_FALSE(o.IsValid(&err));
}

}  // namespace
}  // namespace ps

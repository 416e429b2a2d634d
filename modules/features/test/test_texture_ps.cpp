// The joint (Portilla-Simoncelli-style) statistics and the placement term: what each sees, a
// finite-difference check of each one's gradient alone, and degenerate inputs.
#include "photoscene/core.hpp"
#include "photoscene/features.hpp"
#include "texture_fixtures.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>

namespace ps {
namespace {

using namespace test;  // texture_fixtures.hpp

// Only one joint-statistics group weighted (the descriptor's groups off).
TextureLossOptions onlyGroup(int group) {
  TextureLossOptions o;
  TextureLossWeights& w = o.weights;
  w.colorMean = w.colorStd = w.bandMeanRe = w.bandStdRe = w.bandMeanMag = w.bandStdMag = 0.0f;
  float* ps[5] = {&w.psAutoLowpass, &w.psAutoMagnitude, &w.psCrossOrientation, &w.psCrossScale,
                  &w.psColor};
  *ps[group] = 1.0f;
  return o;
}

// Central differences of the loss at pixels x channels against textureLossBackward, as the
// largest |analytic - numeric| over the largest |numeric|: a wrong or missing adjoint term gives
// errors of order 1; the float pyramid's round-off is about 1e-4 of the largest entry at these
// steps (checkTextureLossGradient's per-entry relative error is dominated by it on the small
// entries of these statistics).
double fdErrorOverLargest(const TextureLossTarget& target, const cv::Mat& render,
                          const std::vector<cv::Point>& pixels, double step) {
  const TextureLossGradientCheck c = checkTextureLossGradient(target, render, pixels, step);
  return c.maxNumeric > 0 ? c.maxAbsError / c.maxNumeric : c.maxAbsError;
}

const char* kGroupNames[5] = {"autoLowpass", "autoMagnitude", "crossOrientation", "crossScale",
                              "color"};

// The default filter bank and joint statistics, and where each group sits in the vector.
class Features_TexturePs : public ::testing::Test {
 protected:
  const TextureDescriptorOptions d;
  const TexturePsOptions o;
  const TexturePsLayout L = texturePsLayout(d, o);
};

TEST_F(Features_TexturePs, layout_and_ranges) {
  EXPECT_EQ(texturePsLagCount(3), 24);
  EXPECT_EQ(L.autoMagnitude, 4 * 24);
  EXPECT_EQ(L.crossOrientation, L.autoMagnitude + 16 * 12);
  EXPECT_EQ(L.crossScale, L.crossOrientation + 4 * 6);
  EXPECT_EQ(L.color, L.crossScale + 3 * 16);
  EXPECT_EQ(L.length, L.color + 9);
  const cv::Size size(96, 96);
  const cv::Mat mask = diskMask(size, {48, 48}, 44);
  for (const cv::Mat& img : {stripes(size, 8, 30), checker(size, 6), noise(size, 1.5, 4)}) {
    const std::vector<float> s = computeTexturePsStatistics(img, mask, d, o);
    ASSERT_EQ(static_cast<int>(s.size()), L.length);
    for (int i = 0; i < L.color; ++i) {  // correlation coefficients
      EXPECT_TRUE(std::isfinite(s[i]));
      EXPECT_LE(std::abs(s[i]), 1.0f + 1e-3f) << i;
    }
    // luminance-level invariance of the correlations: the image times 3
    const std::vector<float> s3 = computeTexturePsStatistics(img * 3.0, mask, d, o);
    for (int i = 0; i < L.color; ++i) EXPECT_NEAR(s3[i], s[i], 2e-3) << i;
  }
}

// Periodicity: the low-pass autocorrelation at the lag of one period along the stripes' normal
// is high for a grating of that period and low (negative) for one of twice the period, whose
// half period that lag is. The marginal descriptor of two such gratings differs only in which
// band holds the energy; here it is the sign of one number.
TEST_F(Features_TexturePs, lowpass_autocorrelation_sees_the_period) {
  const cv::Size size(128, 128);
  const cv::Mat mask = diskMask(size, {64, 64}, 60);
  const std::vector<cv::Point> lags = {{1, 0}, {2, 0}, {3, 0}};
  // level 1 (every 2 pixels): lag (3, 0) = 6 pixels
  auto at = [&](const std::vector<float>& s, int level, cv::Point lag) {
    const int n = texturePsLagCount(o.lowpassRadius);
    int i = 0;
    for (int dy = 0; dy <= o.lowpassRadius; ++dy)
      for (int dx = -o.lowpassRadius; dx <= o.lowpassRadius; ++dx)
        if (dy > 0 || dx > 0) {
          if (dx == lag.x && dy == lag.y) return s[L.autoLowpass + level * n + i];
          ++i;
        }
    return std::nanf("");
  };
  const std::vector<float> p6 = computeTexturePsStatistics(stripes(size, 6.0, 0.0), mask, d, o);
  const std::vector<float> p12 = computeTexturePsStatistics(stripes(size, 12.0, 0.0), mask, d, o);
  std::printf("[   info   ] level-1 lag (3, 0): period 6 %.3f, period 12 %.3f\n", at(p6, 1, {3, 0}),
              at(p12, 1, {3, 0}));
  EXPECT_GT(at(p6, 1, {3, 0}), 0.5f);
  EXPECT_LT(at(p12, 1, {3, 0}), -0.5f);
  // along the stripes (lag (0, 3)) both stay correlated
  EXPECT_GT(at(p6, 1, {0, 3}), 0.8f);
  EXPECT_GT(at(p12, 1, {0, 3}), 0.8f);
}

// Lines: on a grid of thin dark lines (grout) the magnitudes of the bands across the lines
// (orientations 0 and 90 degrees) rise and fall together from one octave to the next, where the
// lines are, while the diagonal bands' do much less; on isotropic noise every orientation is
// alike.
TEST_F(Features_TexturePs, cross_scale_correlation_follows_lines) {
  const cv::Size size(128, 128);
  const cv::Mat mask = diskMask(size, {64, 64}, 60);
  cv::Mat grout(size, CV_32FC3, cv::Scalar::all(0.5));
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      if (x % 16 == 0 || y % 16 == 0) grout.at<cv::Vec3f>(y, x) = cv::Vec3f::all(0.1f);
  // level 0 -> 1, same orientation k: axis (k = 0, 2) minus diagonal (k = 1, 3)
  auto axisMinusDiagonal = [&](const cv::Mat& img) {
    const std::vector<float> s = computeTexturePsStatistics(img, mask, d, o);
    auto at = [&](int k) { return s[L.crossScale + k * 4 + k]; };
    return 0.5 * (at(0) + at(2)) - 0.5 * (at(1) + at(3));
  };
  const double lines = axisMinusDiagonal(grout), iso = axisMinusDiagonal(noise(size, 3.0, 9));
  std::printf("[   info   ] cross-scale, axis minus diagonal: grout %.3f, noise %.3f\n", lines,
              iso);
  EXPECT_GT(lines, 0.3);
  EXPECT_LT(std::abs(iso), 0.1);
}

// Colour: the opponent means and standard deviations scale with the image, the correlations do
// not; a red-green texture has its variation in O1, a gray one none.
TEST_F(Features_TexturePs, opponent_colour) {
  const cv::Size size(64, 64);
  const cv::Mat mask = diskMask(size, {32, 32}, 30);
  cv::Mat redGreen(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      redGreen.at<cv::Vec3f>(y, x) =
          ((x / 4) & 1) ? cv::Vec3f(0.6f, 0.2f, 0.3f) : cv::Vec3f(0.2f, 0.6f, 0.3f);
  const std::vector<float> s = computeTexturePsStatistics(redGreen, mask, d, o);
  EXPECT_NEAR(s[L.color + 0], 0.0, 0.02);  // O1 mean: as much red as green
  EXPECT_GT(s[L.color + 3], 0.25);         // O1 std: 0.4 / sqrt 2 * ... = 0.28
  EXPECT_LT(s[L.color + 4], 1e-3);         // O2 std: R + G is constant
  EXPECT_LT(s[L.color + 5], 1e-3);         // O3 std: the brightness is constant
  const std::vector<float> g =
      computeTexturePsStatistics(noise(size, 1.0, 2, {1, 1, 1}), mask, d, o);
  EXPECT_LT(g[L.color + 3], 1e-4);  // gray: no O1 variation
  EXPECT_GT(g[L.color + 5], 0.1);
}

// Each joint statistic's gradient alone, against central differences at interior, edge and
// outside pixels (zero there), on an irregular mask.
TEST_F(Features_TexturePs, each_group_gradient_matches_finite_differences) {
  const cv::Size size(80, 72);
  cv::Mat mask = diskMask(size, {40, 36}, 28);
  cv::circle(mask, {44, 34}, 5, cv::Scalar(0), cv::FILLED);
  cv::rectangle(mask, cv::Rect(60, 33, 18, 3), cv::Scalar(255), cv::FILLED);
  const cv::Mat photo = stripes(size, 7.0, 30.0) + checker(size, 9) * 0.2;
  const cv::Mat render = noise(size, 1.5, 7) * 0.8 + checker(size, 5) * 0.3;
  std::vector<cv::Point> pixels = randomPixels(mask, true, 14, 1);
  const std::vector<cv::Point> outside = randomPixels(mask, false, 3, 3);
  pixels.insert(pixels.end(), outside.begin(), outside.end());
  pixels.push_back({77, 34});  // the thin arm
  for (int group = 0; group < 5; ++group) {
    const TextureLossTarget target(photo, mask, onlyGroup(group));
    TextureLossParams p;
    p.target = &target;
    p.render = render;
    const double loss = textureLossForward(p);
    EXPECT_GT(loss, 0.0) << kGroupNames[group];
    EXPECT_NEAR(loss, p.psGroupLoss[group], 1e-12 + 1e-9 * loss) << kGroupNames[group];
    const double err = fdErrorOverLargest(target, render, pixels, 3e-3);
    std::printf("[   info   ] %-16s loss %.4g, %zu entries, max error / max gradient %.3g\n",
                kGroupNames[group], loss, 3 * pixels.size(), err);
    EXPECT_LT(err, 1e-2) << kGroupNames[group];
    cv::Mat grad;
    textureLossBackward(p, 1.0f, grad);
    for (const cv::Point& q : outside)
      EXPECT_EQ(grad.at<cv::Vec3f>(q), cv::Vec3f(0, 0, 0)) << kGroupNames[group];
  }
}

// All groups together with the descriptor's: the sum's gradient is still exact, and weights of
// 0 leave the loss exactly as before.
TEST_F(Features_TexturePs, combined_loss_and_defaults_unchanged) {
  const cv::Size size(72, 64);
  const cv::Mat mask = diskMask(size, {36, 32}, 26);
  const cv::Mat photo = checker(size, 6);
  const cv::Mat render = stripes(size, 9.0, 60.0);
  const TextureLossTarget plain(photo, mask);
  TextureLossOptions o;
  o.weights.psAutoLowpass = o.weights.psAutoMagnitude = o.weights.psCrossOrientation = 0.5f;
  o.weights.psCrossScale = o.weights.psColor = 0.5f;
  const TextureLossTarget joint(photo, mask, o);
  EXPECT_TRUE(plain.psStatistics().empty());
  EXPECT_FALSE(joint.psStatistics().empty());
  TextureLossParams a, b;
  a.target = &plain;
  a.render = render;
  b.target = &joint;
  b.render = render;
  const double la = textureLossForward(a), lb = textureLossForward(b);
  double ps = 0;
  for (double v : b.psGroupLoss) ps += v;
  EXPECT_GT(ps, 0.0);
  EXPECT_NEAR(lb, la + ps, 1e-9 * lb);
  EXPECT_LT(fdErrorOverLargest(joint, render, randomPixels(mask, true, 12, 5), 3e-3), 1e-2);
}

// One-pixel, corner, strip and full masks with black, saturated and high-contrast images: every
// joint statistic and the placement loss stay finite, and so do their gradients.
TEST_F(Features_TexturePs, stress_masks_and_images_stay_finite) {
  const cv::Size size(48, 40);
  cv::Mat onePixel = cv::Mat::zeros(size, CV_8UC1);
  onePixel.at<uint8_t>(20, 30) = 255;
  cv::Mat corner = cv::Mat::zeros(size, CV_8UC1);
  corner.at<uint8_t>(0, 0) = 255;
  cv::Mat tiny = cv::Mat::zeros(size, CV_8UC1);
  tiny(cv::Rect(10, 10, 2, 3)).setTo(255);
  cv::Mat full(size, CV_8UC1, cv::Scalar(255));
  cv::Mat strip = cv::Mat::zeros(size, CV_8UC1);
  strip.row(39).setTo(255);
  const cv::Mat black = cv::Mat::zeros(size, CV_32FC3);
  const cv::Mat saturated(size, CV_32FC3, cv::Scalar(1e4, 1e4, 1e4));
  const cv::Mat blackAndWhite = checker(size, 1) * 1e3;
  const cv::Mat tex = noise(size, 1.0, 3);
  TextureLossOptions o;
  o.weights.psAutoLowpass = o.weights.psAutoMagnitude = o.weights.psCrossOrientation = 1.0f;
  o.weights.psCrossScale = o.weights.psColor = 1.0f;
  for (const cv::Mat& mask : {onePixel, corner, tiny, full, strip}) {
    for (const cv::Mat& photo : {black, saturated, blackAndWhite, tex}) {
      const std::vector<float> s = computeTexturePsStatistics(photo, mask);
      ASSERT_TRUE(allFinite(cv::Mat(s)));
      const TextureLossTarget target(photo, mask, o);
      const PlacementLossTarget place(photo, mask);
      for (const cv::Mat& render : {black, saturated, blackAndWhite, tex}) {
        cv::Mat grad;
        ASSERT_TRUE(std::isfinite(lossAndGradient(target, render, grad)));
        ASSERT_TRUE(allFinite(grad));
        cv::Mat pg;
        const double pl = placementLoss(place, render, &pg);
        ASSERT_TRUE(std::isfinite(pl));
        ASSERT_GE(pl, -1e-9);
        ASSERT_LE(pl, 2.0 + 1e-9);
        ASSERT_TRUE(allFinite(pg));
      }
    }
  }
  EXPECT_THROW(computeTexturePsStatistics(tex, cv::Mat::zeros(size, CV_8UC1)), Exception);
  EXPECT_THROW(PlacementLossTarget(tex, cv::Mat::zeros(size, CV_8UC1)), Exception);
  TexturePsOptions bad;
  bad.lowpassRadius = -1;
  EXPECT_THROW(computeTexturePsStatistics(tex, full, {}, bad), Exception);
}

// The key's pooled joint statistics: appended only with psWeight > 0, invariant to a per-channel
// light scale and (exactly, on a square grid) to a 90-degree rotation, and they separate two
// gratings whose marginal statistics are close: a sine and square bars of one period.
TEST_F(Features_TexturePs, key_entries_invariant_and_telling) {
  TextureKeyOptions plain, withPs;
  withPs.psWeight = 1.0f;
  EXPECT_EQ(keyLength(withPs), keyLength(plain) + keyPsLength(withPs.descriptor));
  EXPECT_EQ(keyPsLength(withPs.descriptor), 46);
  const cv::Size size(96, 96);
  const cv::Mat mask = diskMask(size, {47, 47}, 40);  // symmetric under the rotation below
  const cv::Mat img = checker(size, 7) + noise(size, 1.0, 3) * 0.3;
  const std::vector<float> k0 = computeTextureKey(img, mask, withPs);
  ASSERT_EQ(static_cast<int>(k0.size()), keyLength(withPs));
  for (float v : k0) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(computeTextureKey(img, mask, plain),
            std::vector<float>(k0.begin(), k0.begin() + keyLength(plain)));
  cv::Mat scaled = img.clone();
  scaled.forEach<cv::Vec3f>(
      [](cv::Vec3f& p, const int*) { p = cv::Vec3f(2.5f * p[0], 0.4f * p[1], 1.3f * p[2]); });
  EXPECT_LT(descriptorDistance(k0, computeTextureKey(scaled, mask, withPs)), 1e-3);
  cv::Mat rotated, rotatedMask;
  cv::rotate(img, rotated, cv::ROTATE_90_CLOCKWISE);
  cv::rotate(mask, rotatedMask, cv::ROTATE_90_CLOCKWISE);
  const std::vector<float> kr = computeTextureKey(rotated, rotatedMask, withPs);
  const int n0 = keyLength(plain);
  double d = 0;
  for (int i = n0; i < keyLength(withPs); ++i) d += (kr[i] - k0[i]) * (kr[i] - k0[i]);
  EXPECT_LT(std::sqrt(d), 0.05) << "joint entries under a 90-degree rotation";
  cv::Mat bars(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      bars.at<cv::Vec3f>(y, x) = cv::Vec3f::all(((x / 5) & 1) ? 0.6f : 0.2f);
  const std::vector<float> ks = computeTextureKey(stripes(size, 10, 0), mask, withPs);
  const std::vector<float> kb = computeTextureKey(bars, mask, withPs);
  double dPlain = 0, dPs = 0;
  for (int i = 0; i < keyLength(withPs); ++i)
    (i < n0 ? dPlain : dPs) += (ks[i] - kb[i]) * (ks[i] - kb[i]);
  std::printf("[   info   ] sine vs square bars: key distance %.3f, joint entries %.3f\n",
              std::sqrt(dPlain), std::sqrt(dPs));
  EXPECT_GT(std::sqrt(dPs), 0.1);
}

// The placement term: 0 for the same pattern in the same place, rising as a checker is shifted
// by up to half its period, blind to brightness and contrast; its gradient is exact.
TEST(Features_TexturePlacement, sees_the_offset_and_nothing_else) {
  const cv::Size size(96, 80);
  const cv::Mat mask = diskMask(size, {48, 40}, 34);
  const cv::Mat photo = checker(size, 12);
  const PlacementLossTarget target(photo, mask, {2.0});
  // 0 up to the regularizer: 1 - sigma / sqrt(sigma^2 + eps^2), eps = 1e-3 mean luminance
  EXPECT_NEAR(placementLoss(target, photo), 0.0, 1e-4);
  EXPECT_NEAR(placementLoss(target, photo * 2.5 + cv::Scalar::all(0.1)), 0.0, 1e-4);
  double prev = -1;
  for (int shift = 0; shift <= 12; shift += 3) {
    const double l = placementLoss(target, checker(size, 12, {shift, 0}));
    EXPECT_GT(l, prev) << shift;
    prev = l;
  }
  EXPECT_GT(prev, 1.5);  // half a period (12 pixels of 24): anti-correlated
  // noise on top of the right placement costs little
  const double noisy = placementLoss(target, photo + (noise(size, 0.5, 3) - cv::Scalar::all(0.4)));
  const double shifted = placementLoss(target, checker(size, 12, {4, 4}));
  EXPECT_LT(noisy, 0.2 * shifted) << noisy << " vs " << shifted;

  std::vector<cv::Point> pixels = randomPixels(mask, true, 16, 2);
  const std::vector<cv::Point> outside = randomPixels(mask, false, 4, 4);
  pixels.insert(pixels.end(), outside.begin(), outside.end());
  const cv::Mat render = checker(size, 12, {5, 2}) + noise(size, 1.0, 5) * 0.3;
  const TextureLossGradientCheck r = checkPlacementLossGradient(target, render, pixels, 1e-3);
  std::printf("[   info   ] placement gradient: %d entries, max rel error %.3g (noise %.3g)\n",
              r.checked, r.maxRelError, r.noise);
  EXPECT_LT(r.maxRelError, 1e-3) << r.maxAbsError;
  cv::Mat grad;
  placementLoss(target, render, &grad);
  for (const cv::Point& q : outside) EXPECT_EQ(grad.at<cv::Vec3f>(q), cv::Vec3f(0, 0, 0));
  cv::Mat acc = grad.clone();
  placementLoss(target, render, &acc, 2.0f, true);
  EXPECT_LT(cv::norm(acc - 3.0 * grad, cv::NORM_INF), 1e-6 * cv::norm(grad, cv::NORM_INF));
  PlacementLossOptions bad;
  bad.sigma = 0.1;
  EXPECT_THROW(PlacementLossTarget(photo, mask, bad), Exception);
}

}  // namespace
}  // namespace ps

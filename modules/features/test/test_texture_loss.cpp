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

// Mask pixels with at least one 4-neighbour outside the mask.
std::vector<cv::Point> edgePixels(const cv::Mat& mask) {
  std::vector<cv::Point> out;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) {
      if (!mask.at<uint8_t>(y, x)) continue;
      const bool edge = x == 0 || y == 0 || x == mask.cols - 1 || y == mask.rows - 1 ||
                        !mask.at<uint8_t>(y, x - 1) || !mask.at<uint8_t>(y, x + 1) ||
                        !mask.at<uint8_t>(y - 1, x) || !mask.at<uint8_t>(y + 1, x);
      if (edge) out.push_back({x, y});
    }
  return out;
}

// The loss's gradient against central differences, at random interior pixels, random mask-edge
// pixels and pixels outside the mask (whose gradient must be 0), for a render that differs from
// the photo in texture, scale and color (so every group contributes).
TEST(Features_TextureLoss, gradient_matches_finite_differences) {
  const cv::Size size(96, 80);
  // An irregular mask: a disk with a hole and a thin arm.
  cv::Mat mask = diskMask(size, {48, 40}, 30);
  cv::circle(mask, {52, 38}, 6, cv::Scalar(0), cv::FILLED);
  cv::rectangle(mask, cv::Rect(70, 36, 24, 3), cv::Scalar(255), cv::FILLED);
  const cv::Mat photo = stripes(size, 7.0, 30.0);
  cv::Mat render = noise(size, 1.5, 7) * 0.8 + checker(size, 5) * 0.3;
  TextureLossTarget target(photo, mask);
  std::vector<cv::Point> pixels = randomPixels(mask, true, 12, 1);
  const std::vector<cv::Point> edge = edgePixels(mask);
  Rng rng(2);
  for (int i = 0; i < 12; ++i) pixels.push_back(edge[rng.uniformInt(edge.size())]);
  const std::vector<cv::Point> outside = randomPixels(mask, false, 4, 3);
  pixels.insert(pixels.end(), outside.begin(), outside.end());
  const TextureLossGradientCheck r = checkTextureLossGradient(target, render, pixels, 1e-2);
  EXPECT_EQ(r.checked, 3 * 28);
  std::printf(
      "[   info   ] gradient check: %d entries, max rel error %.3g, max abs error %.3g, "
      "finite-difference noise %.3g, floor %.3g\n",
      r.checked, r.maxRelError, r.maxAbsError, r.noise, r.floor);
  // Float filtering limits the finite differences to about 1e-3 relative; a wrong adjoint (a
  // missing flip, a dropped term) gives errors of order 1. Step 1e-2, not 2e-3: with 2e-3 the
  // loss's float round-off (about 8e-8 per difference) was 2 % of a small entry under clang -O1
  // (the sanitizer build) while gcc -O3 happened to put it on a large one.
  EXPECT_LT(r.maxRelError, 2e-2) << "max abs error " << r.maxAbsError << ", floor " << r.floor;

  TextureLossParams p;
  p.target = &target;
  p.render = render;
  textureLossForward(p);
  cv::Mat grad;
  textureLossBackward(p, 1.0f, grad);
  for (const cv::Point& q : outside) EXPECT_EQ(grad.at<cv::Vec3f>(q), cv::Vec3f(0, 0, 0));
  // accumulate adds, gradLoss scales.
  cv::Mat acc = grad.clone();
  textureLossBackward(p, 2.0f, acc, true);
  EXPECT_LT(cv::norm(acc - 3.0 * grad, cv::NORM_INF), 1e-6 * (1.0 + cv::norm(grad, cv::NORM_INF)));
}

// A gradient step along -grad lowers the loss (the gradient is usable by the optimizer).
TEST(Features_TextureLoss, gradient_step_descends) {
  const cv::Size size(128, 96);
  const cv::Mat mask = diskMask(size, {64, 48}, 40);
  TextureLossTarget target(stripes(size, 9.0, 0.0), mask);
  TextureLossParams p;
  p.target = &target;
  p.render = noise(size, 2.0, 11);
  const double l0 = textureLossForward(p);
  cv::Mat grad;
  textureLossBackward(p, 1.0f, grad);
  const double gn = cv::norm(grad);
  ASSERT_GT(gn, 0.0);
  p.render = p.render - grad * (0.05 * l0 / (gn * gn));
  const double l1 = textureLossForward(p);
  EXPECT_LT(l1, l0 * 0.99) << l0 << " -> " << l1;
}

TEST(Features_TextureLoss, zero_for_identical_inputs_and_photo_scale_free) {
  const cv::Size size(160, 120);
  const cv::Mat mask = diskMask(size, {80, 60}, 50);
  const cv::Mat img = noise(size, 2.0, 5);
  TextureLossTarget target(img, mask);
  TextureLossParams p;
  p.target = &target;
  p.render = img;
  EXPECT_EQ(textureLossForward(p), 0.0);
  cv::Mat grad;
  textureLossBackward(p, 1.0f, grad);
  EXPECT_EQ(cv::norm(grad, cv::NORM_INF), 0.0);
  // Normalized by the photo's luminance: scaling photo and render together keeps the loss.
  const cv::Mat other = stripes(size, 6.0, 45.0);
  p.render = other;
  const double l1 = textureLossForward(p);
  TextureLossTarget target3(img * 3.0, mask);
  p.target = &target3;
  p.render = other * 3.0;
  const double l3 = textureLossForward(p);
  EXPECT_GT(l1, 0.0);
  EXPECT_NEAR(l3 / l1, 1.0, 1e-3);
}

// White pixel noise of a known level added to an image (independent per pixel and channel).
cv::Mat withPixelNoise(const cv::Mat& img, double sigma, uint64_t seed) {
  Rng rng(seed);
  cv::Mat out = img.clone();
  for (int y = 0; y < out.rows; ++y)
    for (int x = 0; x < out.cols; ++x)
      for (int c = 0; c < 3; ++c)
        out.at<cv::Vec3f>(y, x)[c] += static_cast<float>(sigma * rng.normal());
  return out;
}

// The noise level is read back from a shaded (linear ramp) and a striped image within 10 %;
// a noise-free image reads near 0; too few interior pixels read 0.
TEST(Features_PixelNoise, estimate_recovers_the_added_level) {
  const cv::Size size(160, 120);
  const cv::Mat mask = diskMask(size, {80, 60}, 50);
  cv::Mat ramp(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      ramp.at<cv::Vec3f>(y, x) = cv::Vec3f(0.2f, 0.25f, 0.3f) * (1.0f + x / 160.0f + y / 240.0f);
  for (const double sigma : {0.005, 0.02, 0.05}) {
    for (const cv::Mat& clean : {ramp, stripes(size, 24.0, 30.0)}) {
      const cv::Vec3d est = estimatePixelNoise(withPixelNoise(clean, sigma, 11), mask);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(est[c] / sigma, 1.0, 0.1) << sigma << " ch " << c;
    }
  }
  EXPECT_LT(estimatePixelNoise(ramp, mask)[0], 1e-4);
  EXPECT_EQ(estimatePixelNoise(withPixelNoise(ramp, 0.02, 3), diskMask(size, {80, 60}, 3)),
            cv::Vec3d(0, 0, 0));
}

// A render carries no pixel noise. Against a noisy photo of a plain surface, the clean flat
// render's loss (which was mostly the noise's band energy) drops by 10x with the noise floor,
// and a grain texture that only mimics the noise no longer beats it; on a striped photo the clean
// stripes still win, and the target keeps the stripes' band energy.
TEST(Features_PixelNoise, noise_floor_lets_a_clean_render_match_a_noisy_photo) {
  const cv::Size size(160, 120);
  const cv::Mat mask = diskMask(size, {80, 60}, 50);
  const cv::Mat flat(size, CV_32FC3, cv::Scalar(0.4, 0.36, 0.32));
  const cv::Mat photo = withPixelNoise(flat, 0.03, 5);
  cv::Mat grain = noise(size, 0.7, 9);  // fine grain, std 0.12 ...
  grain = (grain - cv::Scalar::all(0.4)) * 0.3 + flat;  // ... scaled to about the noise's level
  TextureLossOptions on;
  on.photoNoiseFloor = true;
  TextureLossTarget plain(photo, mask), floored(photo, mask, on);
  EXPECT_EQ(plain.photoNoise(), cv::Vec3d(0, 0, 0));
  EXPECT_NEAR(floored.photoNoise()[0] / 0.03, 1.0, 0.1);
  auto loss = [](const TextureLossTarget& t, const cv::Mat& render) {
    TextureLossParams p;
    p.target = &t;
    p.render = render;
    return textureLossForward(p);
  };
  std::printf("plain photo: flat %.4g -> %.4g, grain %.4g -> %.4g\n", loss(plain, flat),
              loss(floored, flat), loss(plain, grain), loss(floored, grain));
  EXPECT_LT(loss(floored, flat), 0.1 * loss(plain, flat));
  EXPECT_LT(loss(plain, grain), loss(plain, flat));  // what went wrong without the floor
  EXPECT_LT(loss(floored, flat), loss(floored, grain));

  const cv::Mat lines = stripes(size, 12.0, 30.0);
  const cv::Mat noisyLines = withPixelNoise(lines, 0.03, 6);
  TextureLossTarget striped(noisyLines, mask, on), stripedPlain(noisyLines, mask);
  const cv::Mat wider = stripes(size, 12.0 * 1.15, 30.0);
  std::printf("striped photo: lines %.4g -> %.4g, 15 %% wider %.4g -> %.4g, flat %.4g\n",
              loss(stripedPlain, lines), loss(striped, lines), loss(stripedPlain, wider),
              loss(striped, wider), loss(striped, flat));
  // the floor takes off the noise, not the stripes: the clean stripes match better than
  // without it, and better than stripes 15 % wider or the flat render
  EXPECT_LT(loss(striped, lines), 0.5 * loss(stripedPlain, lines));
  EXPECT_LT(loss(striped, lines), loss(striped, wider));
  EXPECT_LT(loss(striped, lines), 0.2 * loss(striped, flat));
}

// The loss grows monotonically as a grating's period departs from the target's, both ways.
TEST(Features_TextureLoss, grows_monotonically_with_frequency_departure) {
  const cv::Size size(200, 160);
  const cv::Mat mask = diskMask(size, {100, 80}, 70);
  const double period0 = 10.0;
  TextureLossTarget target(stripes(size, period0, 20.0), mask);
  TextureLossParams p;
  p.target = &target;
  for (int dir : {-1, +1}) {
    double prev = -1.0;
    for (int i = 0; i <= 6; ++i) {
      const double period = period0 * std::pow(1.15, dir * i);
      p.render = stripes(size, period, 20.0);
      const double l = textureLossForward(p);
      if (i == 0) {
        EXPECT_LT(l, 1e-10);
      }
      EXPECT_GT(l, prev) << "period " << period;
      prev = l;
    }
  }
}

// No NaN or Inf from degenerate masks and extreme images; the empty mask throws.
TEST(Features_TextureLoss, stress_masks_and_images_stay_finite) {
  const cv::Size size(64, 48);
  cv::Mat onePixel = cv::Mat::zeros(size, CV_8UC1);
  onePixel.at<uint8_t>(20, 30) = 255;
  cv::Mat corner = cv::Mat::zeros(size, CV_8UC1);
  corner.at<uint8_t>(0, 0) = 255;
  cv::Mat full(size, CV_8UC1, cv::Scalar(255));
  cv::Mat strip = cv::Mat::zeros(size, CV_8UC1);
  strip.row(47).setTo(255);
  cv::Mat ring = diskMask(size, {32, 24}, 20);
  cv::circle(ring, {32, 24}, 15, cv::Scalar(0), cv::FILLED);
  const cv::Mat black = cv::Mat::zeros(size, CV_32FC3);
  const cv::Mat saturated(size, CV_32FC3, cv::Scalar(1e4, 1e4, 1e4));
  cv::Mat blackAndWhite = checker(size, 1) * 1e3;  // pixel-scale, very high contrast
  const cv::Mat tex = noise(size, 1.0, 3);
  for (const cv::Mat& mask : {onePixel, corner, full, strip, ring}) {
    for (const cv::Mat& photo : {black, saturated, blackAndWhite, tex}) {
      for (const cv::Mat& render : {black, saturated, tex}) {
        TextureLossTarget target(photo, mask);
        ASSERT_TRUE(allFinite(cv::Mat(target.descriptor().values)));
        cv::Mat grad;
        ASSERT_TRUE(std::isfinite(lossAndGradient(target, render, grad)));
        ASSERT_TRUE(allFinite(grad));
      }
    }
  }
  const cv::Mat empty = cv::Mat::zeros(size, CV_8UC1);
  EXPECT_THROW(TextureLossTarget(tex, empty), Exception);
  TextureLossTarget target(tex, full);
  TextureLossParams p;
  p.target = &target;
  p.render = cv::Mat::zeros(10, 10, CV_32FC3);
  EXPECT_THROW(textureLossForward(p), Exception);
  p.render = tex.clone();
  p.render.at<cv::Vec3f>(3, 3)[1] = std::nanf("");
  EXPECT_THROW(textureLossForward(p), Exception);
}

// The one-pixel mask's gradient is still exact (its statistics rest on one pixel at every scale).
TEST(Features_TextureLoss, one_pixel_mask_gradient) {
  const cv::Size size(40, 40);
  cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
  mask.at<uint8_t>(20, 21) = 255;
  TextureLossTarget target(noise(size, 1.0, 1), mask);
  const TextureLossGradientCheck r =
      checkTextureLossGradient(target, stripes(size, 5.0, 10.0), {{21, 20}, {22, 20}}, 2e-3);
  EXPECT_LT(r.maxRelError, 2e-2) << r.maxAbsError;
}

// The spectral shape group (weights.bandShape): its gradient against central differences (the
// group alone, every other weight 0), its blindness to contrast (the photo's deviations from its
// mean doubled: the same shares), and what it sees (a period of 7 against 14 pixels).
TEST(Features_TextureLoss, band_shape_gradient_and_what_it_sees) {
  const cv::Size size(96, 80);
  cv::Mat mask = diskMask(size, {48, 40}, 30);
  cv::rectangle(mask, cv::Rect(70, 36, 24, 3), cv::Scalar(255), cv::FILLED);
  TextureLossOptions o;
  TextureLossWeights& w = o.weights;
  w.colorMean = w.colorStd = w.bandMeanRe = w.bandStdRe = w.bandMeanMag = w.bandStdMag = 0.0f;
  w.bandShape = 10.0f;
  const cv::Mat photo = stripes(size, 7.0, 30.0);
  const TextureLossTarget target(photo, mask, o);
  const cv::Mat render = noise(size, 1.5, 7) * 0.8 + checker(size, 5) * 0.3;
  std::vector<cv::Point> pixels = randomPixels(mask, true, 12, 1);
  const std::vector<cv::Point> outside = randomPixels(mask, false, 3, 3);
  pixels.insert(pixels.end(), outside.begin(), outside.end());
  const TextureLossGradientCheck r = checkTextureLossGradient(target, render, pixels, 1e-2);
  EXPECT_GT(r.maxNumeric, 0.0);
  EXPECT_LT(r.maxRelError, 2e-2) << "max abs error " << r.maxAbsError << ", floor " << r.floor;

  TextureLossParams p;
  p.target = &target;
  const cv::Scalar mean = cv::mean(photo, mask);
  p.render = (photo - mean) * 2.0 + mean;
  textureLossForward(p);
  EXPECT_LT(p.shapeLoss, 1e-6);
  p.render = stripes(size, 14.0, 30.0);
  textureLossForward(p);
  EXPECT_GT(p.shapeLoss, 0.1);
  EXPECT_DOUBLE_EQ(p.loss, p.shapeLoss);  // the other groups are off
  // a flat render has no band energy: finite, no gradient
  p.render = cv::Mat(size, CV_32FC3, cv::Scalar::all(0.4));
  cv::Mat grad;
  EXPECT_TRUE(std::isfinite(lossAndGradient(target, p.render, grad)));
  EXPECT_EQ(cv::norm(grad, cv::NORM_INF), 0.0);
}

// The spectral shape's target has the photo's pixel noise taken off: a render carries none, and
// the noise's energy in the fine bands would read as structure the render must make up. A clean
// render of the photo's stripes then scores far below the same render with the photo's noise
// added (without the correction it is the other way round).
TEST(Features_TextureLoss, band_shape_takes_the_photos_noise_off) {
  const cv::Size size(128, 96);
  const cv::Mat mask = diskMask(size, {64, 48}, 44);
  const cv::Mat clean = stripes(size, 9.0, 20.0);
  cv::Mat grain(size, CV_32FC3);
  cv::RNG rng(7);
  rng.fill(grain, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(0.06));
  const cv::Mat photo = clean + grain;
  TextureLossOptions o;
  TextureLossWeights& w = o.weights;
  w.colorMean = w.colorStd = w.bandMeanRe = w.bandStdRe = w.bandMeanMag = w.bandStdMag = 0.0f;
  w.bandShape = 1.0f;
  const TextureLossTarget target(photo, mask, o);
  TextureLossParams p;
  p.target = &target;
  p.render = clean;
  textureLossForward(p);
  const double cleanLoss = p.shapeLoss;
  cv::Mat grain2(size, CV_32FC3);
  rng.fill(grain2, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(0.06));
  p.render = clean + grain2;
  textureLossForward(p);
  const double noisyLoss = p.shapeLoss;
  EXPECT_LT(cleanLoss, 0.25 * noisyLoss) << cleanLoss << " vs " << noisyLoss;
  EXPECT_TRUE(std::isfinite(cleanLoss) && std::isfinite(noisyLoss));
}

TEST(Features_TextureLoss, options_are_validated) {
  TextureLossOptions o;
  std::string err;
  EXPECT_TRUE(o.IsValid(&err)) << err;
  o.weights.scale = {1.0f, 1.0f};
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("numScales"), std::string::npos);
  o.weights.scale.clear();
  o.weights.bandStdMag = -1.0f;
  EXPECT_FALSE(o.IsValid(&err));
  o = {};
  o.descriptor.centerFrequency = 0.7;
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_THROW(TextureLossTarget(cv::Mat::zeros(8, 8, CV_32FC3), cv::Mat::ones(8, 8, CV_8UC1), o),
               Exception);
}

}  // namespace
}  // namespace ps

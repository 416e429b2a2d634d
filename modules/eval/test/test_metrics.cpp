#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "photoscene/core.hpp"
#include "photoscene/eval.hpp"

namespace ps::eval {
namespace {

cv::Mat constant(int w, int h, float v) { return cv::Mat(h, w, CV_32FC3, cv::Scalar(v, v, v)); }

cv::Mat randomImage(int w, int h, uint64_t seed) {
  Rng rng(seed);
  cv::Mat m(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      m.at<cv::Vec3f>(y, x) = cv::Vec3f(rng.uniform(), rng.uniform(), rng.uniform());
  return m;
}

TEST(Eval_Metrics, rmse_and_psnr_match_hand_computed_values) {
  cv::Mat a = constant(2, 2, 0.5f), b = constant(2, 2, 0.5f);
  b.at<cv::Vec3f>(1, 0)[0] = 0.9f;
  // one of 12 terms differs by 0.4
  EXPECT_NEAR(rmse(a, b, ColorSpace::Linear), std::sqrt(0.16 / 12), 1e-7);
  cv::Mat mask = cv::Mat::zeros(2, 2, CV_8UC1);
  mask.at<uint8_t>(1, 0) = 255;
  EXPECT_NEAR(rmse(a, b, ColorSpace::Linear, mask), std::sqrt(0.16 / 3), 1e-7);
  mask.setTo(0);
  mask.at<uint8_t>(0, 0) = 255;
  EXPECT_EQ(rmse(a, b, ColorSpace::Linear, mask), 0.0);
  EXPECT_TRUE(std::isnan(rmse(a, b, ColorSpace::Linear, cv::Mat::zeros(2, 2, CV_8UC1))));
  // PSNR: uniform error of 0.1 in linear [0, 1] -> exactly 20 dB
  const cv::Mat c = constant(3, 3, 0.25f), d = constant(3, 3, 0.35f);
  EXPECT_NEAR(psnr(c, d, ColorSpace::Linear), 20.0, 1e-5);
  EXPECT_TRUE(std::isinf(psnr(c, c, ColorSpace::Linear)));
  // sRGB scale: black against white is 255 apart, 0 dB
  EXPECT_NEAR(rmse(constant(2, 2, 0.f), constant(2, 2, 1.f), ColorSpace::Srgb255), 255.0, 1e-4);
  EXPECT_NEAR(psnr(constant(2, 2, 0.f), constant(2, 2, 1.f), ColorSpace::Srgb255), 0.0, 1e-6);
  // sRGB encode of linear 0.214041140 is 0.5 -> 127.5
  EXPECT_NEAR(rmse(constant(1, 1, 0.f), constant(1, 1, 0.21404114f), ColorSpace::Srgb255), 127.5, 1e-3);
  // saturated values clamp on the display scale but not in linear
  EXPECT_NEAR(rmse(constant(1, 1, 1.f), constant(1, 1, 4.f), ColorSpace::Srgb255), 0.0, 1e-6);
  EXPECT_NEAR(rmse(constant(1, 1, 1.f), constant(1, 1, 4.f), ColorSpace::Linear), 3.0, 1e-6);
}

/// Direct double-precision SSIM of one channel (Wang et al. 2004), reflect-101 borders.
double referenceSsim(const cv::Mat& a, const cv::Mat& b, int channel, double range) {
  const int r = 5;
  const double sigma = 1.5, c1 = std::pow(0.01 * range, 2), c2 = std::pow(0.03 * range, 2);
  double w[11], wsum = 0;
  for (int i = -r; i <= r; ++i) wsum += (w[i + r] = std::exp(-i * i / (2 * sigma * sigma)));
  for (double& x : w) x /= wsum;
  auto at = [&](const cv::Mat& m, int y, int x) {
    y = cv::borderInterpolate(y, m.rows, cv::BORDER_REFLECT_101);
    x = cv::borderInterpolate(x, m.cols, cv::BORDER_REFLECT_101);
    return static_cast<double>(m.at<cv::Vec3f>(y, x)[channel]);
  };
  double total = 0;
  for (int y = 0; y < a.rows; ++y) {
    for (int x = 0; x < a.cols; ++x) {
      double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
      for (int dy = -r; dy <= r; ++dy) {
        for (int dx = -r; dx <= r; ++dx) {
          const double k = w[dy + r] * w[dx + r];
          const double va = at(a, y + dy, x + dx), vb = at(b, y + dy, x + dx);
          ma += k * va;
          mb += k * vb;
          saa += k * va * va;
          sbb += k * vb * vb;
          sab += k * va * vb;
        }
      }
      const double va = saa - ma * ma, vb = sbb - mb * mb, cov = sab - ma * mb;
      total += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
    }
  }
  return total / a.total();
}

TEST(Eval_Metrics, ssim_matches_a_direct_implementation) {
  const cv::Mat a = randomImage(24, 20, 1);
  cv::Mat b;
  cv::GaussianBlur(a, b, cv::Size(5, 5), 1.0);
  b.convertTo(b, CV_32F, 0.8, 0.05);  // per channel: scale and offset
  for (ColorSpace space : {ColorSpace::Linear, ColorSpace::Srgb255}) {
    const cv::Mat ma = toMetricSpace(a, space), mb = toMetricSpace(b, space);
    const double range = space == ColorSpace::Linear ? 1.0 : 255.0;
    double ref = 0;
    for (int c = 0; c < 3; ++c) ref += referenceSsim(ma, mb, c, range) / 3;
    EXPECT_NEAR(ssim(a, b, space), ref, 2e-4) << toString(space);
    EXPECT_LT(ssim(a, b, space), 0.95);
  }
  EXPECT_NEAR(ssim(a, a, ColorSpace::Srgb255), 1.0, 1e-6);
}

TEST(Eval_Metrics, gmsd_is_zero_for_identical_and_grows_with_blur) {
  const cv::Mat a = randomImage(64, 48, 3);
  EXPECT_NEAR(gmsd(a, a, ColorSpace::Srgb255), 0.0, 1e-9);
  double previous = 0;
  for (double sigma : {0.5, 1.0, 2.0, 4.0}) {
    cv::Mat b;
    cv::GaussianBlur(a, b, cv::Size(0, 0), sigma);
    const double g = gmsd(a, b, ColorSpace::Srgb255);
    EXPECT_GT(g, previous) << sigma;
    previous = g;
  }
  EXPECT_GT(previous, 0.1);
  // a global brightness change that keeps edges changes GMSD far less than blur
  cv::Mat darker;
  a.convertTo(darker, CV_32F, 0.9);
  EXPECT_LT(gmsd(a, darker, ColorSpace::Srgb255), previous);
}

TEST(Eval_Metrics, compare_images_fills_every_metric_and_refuses_mismatched_inputs) {
  const cv::Mat a = randomImage(32, 32, 4), b = randomImage(32, 32, 5);
  const ImageMetrics m = compareImages(a, b, ColorSpace::Srgb255);
  EXPECT_GT(m.rmse, 0);
  EXPECT_TRUE(std::isfinite(m.psnr));
  EXPECT_LT(m.ssim, 0.5);
  EXPECT_GT(m.gmsd, 0);
  EXPECT_THROW(rmse(a, randomImage(16, 16, 6), ColorSpace::Linear), Exception);
  cv::Mat nan = a.clone();
  nan.at<cv::Vec3f>(0, 0)[0] = std::nanf("");
  EXPECT_TRUE(std::isfinite(rmse(nan, b, ColorSpace::Srgb255)));
}

}  // namespace
}  // namespace ps::eval

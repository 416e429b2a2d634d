// ps::denoise on synthetic images with a known clean signal: noise removed, edges in normal and
// depth kept, albedo textures kept sharp (demodulation), degenerate inputs, thread-count
// determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "photoscene/core/color.hpp"
#include "photoscene/core/parallel.hpp"
#include "photoscene/raytrace/denoise.hpp"

namespace ps {
namespace {

double rmseOver(const cv::Mat& a, const cv::Mat& b, const cv::Rect& r) {
  cv::Mat d;
  cv::absdiff(a(r), b(r), d);
  d = d.mul(d);
  const cv::Scalar s = cv::mean(d);
  return std::sqrt((s[0] + s[1] + s[2]) / 3.0);
}
double rmseAll(const cv::Mat& a, const cv::Mat& b) {
  return rmseOver(a, b, cv::Rect(0, 0, a.cols, a.rows));
}

bool finiteNonNegative(const cv::Mat& m) {
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      for (int k = 0; k < 3; ++k) {
        const float v = m.at<cv::Vec3f>(y, x)[k];
        if (!std::isfinite(v) || v < 0) return false;
      }
  return true;
}

// A flat wall facing the camera: unit normal +z, depth 2 m, gray albedo 0.5.
DenoiseGuides flatGuides(int w, int h, float albedo = 0.5f) {
  DenoiseGuides g;
  g.albedo = cv::Mat(h, w, CV_32FC3, cv::Scalar::all(albedo));
  g.normal = cv::Mat(h, w, CV_32FC3, cv::Scalar(0, 0, 1));
  g.depth = cv::Mat(h, w, CV_32FC1, cv::Scalar(2.0));
  return g;
}

// noisy = clean * (1 + sigma N(0, 1)), clamped at 0: Monte-Carlo-like noise proportional to the
// signal.
cv::Mat addNoise(const cv::Mat& clean, float sigma, uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat n(clean.size(), CV_32FC3);
  rng.fill(n, cv::RNG::NORMAL, 0.0, sigma);
  cv::Mat noisy = clean.mul(cv::Scalar::all(1.0) + n);
  return cv::max(noisy, 0.0);
}

// Smooth irradiance: a horizontal ramp with a soft vertical bump.
cv::Mat smoothIrradiance(int w, int h) {
  cv::Mat e(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v =
          0.4f + 0.6f * x / w + 0.2f * std::exp(-std::pow((y - h / 2.0f) / (h / 4.0f), 2.0f));
      e.at<cv::Vec3f>(y, x) = cv::Vec3f(v, 0.9f * v, 0.8f * v);
    }
  return e;
}

TEST(Raytrace_Denoise, removes_most_of_the_noise_of_a_smooth_image) {
  const int w = 128, h = 96;
  const DenoiseGuides g = flatGuides(w, h);
  const cv::Mat clean = smoothIrradiance(w, h).mul(g.albedo);
  const cv::Mat noisy = addNoise(clean, 0.3f, 1);
  const cv::Mat out = denoise(g, noisy);
  const double before = rmseAll(noisy, clean), after = rmseAll(out, clean);
  EXPECT_GT(before, 0.05);
  EXPECT_LT(after, before / 6.0) << "before " << before << " after " << after;
  EXPECT_TRUE(finiteNonNegative(out));
}

TEST(Raytrace_Denoise, given_variance_is_used_and_also_denoises) {
  const int w = 128, h = 96;
  DenoiseGuides g = flatGuides(w, h);
  const cv::Mat clean = smoothIrradiance(w, h).mul(g.albedo);
  const cv::Mat noisy = addNoise(clean, 0.3f, 2);
  // The true variance of each pixel's luminance: (0.3 * lum(clean))^2.
  g.variance.create(h, w, CV_32FC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const cv::Vec3f c = clean.at<cv::Vec3f>(y, x);
      const float l = luminance(c);
      g.variance.at<float>(y, x) = 0.09f * l * l;
    }
  const cv::Mat out = denoise(g, noisy);
  EXPECT_LT(rmseAll(out, clean), rmseAll(noisy, clean) / 6.0);
  // A variance 1e-8 of the truth makes the luminance edge-stop reject every neighbour: the
  // guide is read (the image stays noisy).
  g.variance *= 1e-8;
  const cv::Mat kept = denoise(g, noisy);
  EXPECT_GT(rmseAll(kept, clean), 0.8 * rmseAll(noisy, clean));
}

// Two surfaces meeting at column w/2, told apart by the normal only or by the depth only; the
// left is lit 5 x brighter. Near the edge the filter must not average across.
void expectEdgeKept(bool byNormal) {
  const int w = 96, h = 64;
  DenoiseGuides g = flatGuides(w, h);
  cv::Mat irr(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool left = x < w / 2;
      irr.at<cv::Vec3f>(y, x) = left ? cv::Vec3f(1.0f, 1.0f, 1.0f) : cv::Vec3f(0.2f, 0.2f, 0.2f);
      if (!left) {
        if (byNormal)
          g.normal.at<cv::Vec3f>(y, x) = cv::Vec3f(1, 0, 0);
        else
          g.depth.at<float>(y, x) = 3.0f;
      }
    }
  const cv::Mat clean = irr.mul(g.albedo);
  const cv::Mat noisy = addNoise(clean, 0.3f, 3);
  const cv::Mat out = denoise(g, noisy);
  // 3-pixel bands on each side of the edge, away from the image border.
  const cv::Rect leftBand(w / 2 - 3, 4, 3, h - 8), rightBand(w / 2, 4, 3, h - 8);
  const double l = cv::mean(out(leftBand))[1], r = cv::mean(out(rightBand))[1];
  EXPECT_NEAR(l, 0.5, 0.5 * 0.04) << (byNormal ? "normal" : "depth") << " edge: left band bled";
  EXPECT_NEAR(r, 0.1, 0.1 * 0.06) << (byNormal ? "normal" : "depth") << " edge: right band bled";
  // And the bands themselves are denoised.
  EXPECT_LT(rmseOver(out, clean, rightBand), 0.5 * rmseOver(noisy, clean, rightBand));
  EXPECT_LT(rmseOver(out, clean, leftBand), 0.5 * rmseOver(noisy, clean, leftBand));
}

TEST(Raytrace_Denoise, keeps_an_edge_in_the_normal) {
  expectEdgeKept(true);
}
TEST(Raytrace_Denoise, keeps_an_edge_in_the_depth) {
  expectEdgeKept(false);
}

TEST(Raytrace_Denoise, checker_albedo_stays_sharp) {
  const int w = 128, h = 96, cell = 3;
  DenoiseGuides g = flatGuides(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool dark = ((x / cell) + (y / cell)) % 2;
      g.albedo.at<cv::Vec3f>(y, x) =
          dark ? cv::Vec3f(0.05f, 0.1f, 0.1f) : cv::Vec3f(0.9f, 0.8f, 0.7f);
    }
  const cv::Mat clean = smoothIrradiance(w, h).mul(g.albedo);
  const cv::Mat noisy = addNoise(clean, 0.3f, 4);
  const cv::Mat out = denoise(g, noisy);
  const double before = rmseAll(noisy, clean), after = rmseAll(out, clean);
  EXPECT_LT(after, before / 5.0) << "before " << before << " after " << after;
  // Sharp: the contrast of the texture is kept, pixel by pixel (a blurred checker of 3-px cells
  // would pull dark and bright cells toward their mean, ~0.5x the error of the whole signal).
  double maxRel = 0;
  for (int y = 8; y < h - 8; ++y)
    for (int x = 8; x < w - 8; ++x) {
      const float c = clean.at<cv::Vec3f>(y, x)[1], o = out.at<cv::Vec3f>(y, x)[1];
      maxRel = std::max(maxRel, double(std::abs(o - c) / c));
    }
  EXPECT_LT(maxRel, 0.25);
  // Without demodulation (albedo guide 1) the same filter loses the texture: the guide matters.
  DenoiseGuides flat = g;
  flat.albedo = cv::Mat(h, w, CV_32FC3, cv::Scalar::all(1.0));
  DenoiseOptions strong;
  strong.sigmaLuminance = 1e6f;  // luminance stop off: only the guides can keep the texture
  EXPECT_LT(rmseAll(denoise(g, noisy, strong), clean),
            0.5 * rmseAll(denoise(flat, noisy, strong), clean));
}

TEST(Raytrace_Denoise, background_pixels_pass_through) {
  const int w = 40, h = 30;
  DenoiseGuides g = flatGuides(w, h);
  g.depth(cv::Rect(0, 0, w, h / 2)).setTo(0.0);
  g.normal(cv::Rect(0, 0, w, h / 2)).setTo(cv::Scalar::all(0));
  g.albedo(cv::Rect(0, 0, w, h / 2)).setTo(cv::Scalar::all(1));
  cv::Mat clean(h, w, CV_32FC3, cv::Scalar::all(0.7));  // environment 0.7, wall 0.5 x 0.3
  clean(cv::Rect(0, h / 2, w, h - h / 2)).setTo(cv::Scalar::all(0.15));
  const cv::Mat noisy = addNoise(clean, 0.3f, 5);
  const cv::Mat out = denoise(g, noisy);
  EXPECT_EQ(cv::norm(out(cv::Rect(0, 0, w, h / 2)), noisy(cv::Rect(0, 0, w, h / 2)), cv::NORM_INF),
            0.0);
  // No environment value leaks into the surface's first row: it is denoised toward 0.15.
  const cv::Rect firstRow(4, h / 2, w - 8, 1);
  EXPECT_NEAR(cv::mean(out(firstRow))[0], 0.15, 0.15 * 0.05);
  EXPECT_LT(rmseOver(out, clean, firstRow), 0.5 * rmseOver(noisy, clean, firstRow));
}

TEST(Raytrace_Denoise, degenerate_inputs_give_finite_non_negative_output) {
  const float inf = std::numeric_limits<float>::infinity(),
              nan = std::numeric_limits<float>::quiet_NaN();
  // Zero albedo, black image.
  {
    DenoiseGuides g = flatGuides(16, 12, 0.0f);
    const cv::Mat out = denoise(g, cv::Mat(12, 16, CV_32FC3, cv::Scalar::all(0)));
    EXPECT_TRUE(finiteNonNegative(out));
    EXPECT_EQ(cv::norm(out, cv::NORM_INF), 0.0);
  }
  // Zero albedo with light (specular-only surface), saturated values, NaN, Inf, negative input
  // and NaN guides.
  {
    DenoiseGuides g = flatGuides(16, 12, 0.0f);
    cv::Mat img = addNoise(cv::Mat(12, 16, CV_32FC3, cv::Scalar::all(0.05)), 0.3f, 6);
    img.at<cv::Vec3f>(3, 3) = cv::Vec3f(1e30f, 1e30f, 1e30f);
    img.at<cv::Vec3f>(4, 4) = cv::Vec3f(nan, inf, -1.0f);
    g.normal.at<cv::Vec3f>(5, 5) = cv::Vec3f(nan, 0, 0);
    g.depth.at<float>(6, 6) = nan;
    g.albedo.at<cv::Vec3f>(7, 7) = cv::Vec3f(nan, 1, 1);
    EXPECT_TRUE(finiteNonNegative(denoise(g, img)));
  }
  // 1 x 1 and one row.
  for (cv::Size s : {cv::Size(1, 1), cv::Size(7, 1), cv::Size(1, 7)}) {
    DenoiseGuides g = flatGuides(s.width, s.height);
    const cv::Mat img(s, CV_32FC3, cv::Scalar(0.3, 0.2, 0.1));
    const cv::Mat out = denoise(g, img);
    ASSERT_EQ(out.size(), s);
    EXPECT_LT(cv::norm(out, img, cv::NORM_INF), 1e-6);  // constant stays constant
  }
  // Empty image.
  EXPECT_TRUE(denoise(flatGuides(0, 0), cv::Mat(0, 0, CV_32FC3)).empty());
}

TEST(Raytrace_Denoise, rejects_bad_guides_and_options) {
  DenoiseGuides g = flatGuides(8, 8);
  const cv::Mat img(8, 8, CV_32FC3, cv::Scalar::all(0.5));
  EXPECT_THROW(denoise(g, cv::Mat(8, 9, CV_32FC3)), std::invalid_argument);
  EXPECT_THROW(denoise(g, cv::Mat(8, 8, CV_8UC3)), std::invalid_argument);
  DenoiseGuides badDepth = g;
  badDepth.depth = cv::Mat(8, 8, CV_64FC1);
  EXPECT_THROW(denoise(badDepth, img), std::invalid_argument);
  DenoiseOptions o;
  o.sigmaLuminance = 0;
  EXPECT_THROW(denoise(g, img, o), std::invalid_argument);
}

TEST(Raytrace_Denoise, same_bits_on_any_thread_count) {
  const int w = 97, h = 61;
  DenoiseGuides g = flatGuides(w, h);
  g.depth(cv::Rect(50, 0, 47, 61)).setTo(3.0);
  const cv::Mat noisy = addNoise(smoothIrradiance(w, h).mul(g.albedo), 0.3f, 7);
  cv::Mat one, many;
  {
    ThreadLimit limit(1);
    one = denoise(g, noisy);
  }
  {
    ThreadLimit limit(4);
    many = denoise(g, noisy);
  }
  EXPECT_EQ(cv::norm(one, many, cv::NORM_INF), 0.0);
}

TEST(Raytrace_Denoise, variance_from_halves_estimates_the_mean_variance) {
  // a, b: means of n samples each of N(1, s^2); the mean of both has variance s^2 / (2n).
  const int w = 64, h = 64;
  const float sd = 0.2f;  // standard deviation of each half
  cv::Mat a(h, w, CV_32FC3), b(h, w, CV_32FC3);
  cv::RNG rng(8);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float na = float(rng.gaussian(sd)), nb = float(rng.gaussian(sd));
      a.at<cv::Vec3f>(y, x) = cv::Vec3f::all(1 + na);
      b.at<cv::Vec3f>(y, x) = cv::Vec3f::all(1 + nb);
    }
  const double meanVar = cv::mean(varianceFromHalves(a, b))[0];
  EXPECT_NEAR(meanVar, sd * sd / 2, 0.1 * sd * sd / 2);
}

}  // namespace
}  // namespace ps

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>

#include "photoscene/core.hpp"
#include "photoscene/optim/uv_spectrum.hpp"

namespace ps {
namespace {

// A periodic pattern p(t) with period 1 in t: a checker of 8 x 8 cells plus a 36-cycle grating.
float pattern(double tu, double tv) {
  const int cu = static_cast<int>(std::floor(tu * 8)), cv = static_cast<int>(std::floor(tv * 8));
  const double check = ((cu + cv) & 1) ? 0.7 : 0.3;
  return static_cast<float>(check + 0.1 * std::cos(2 * CV_PI * 36 * tv));
}

// raster(y, x) = pattern(s R (x, y) cell)
cv::Mat raster(int M, double cell, double logScale, double rotation) {
  cv::Mat r(M, M, CV_32F);
  const double s = std::exp(logScale), c = std::cos(rotation), sn = std::sin(rotation);
  for (int y = 0; y < M; ++y)
    for (int x = 0; x < M; ++x) {
      double sum = 0;  // a 4 x 4 box filter per cell, as a camera pixel integrates
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const double u = (x + (i + 0.5) / 4) * cell, v = (y + (j + 0.5) / 4) * cell;
          sum += pattern(s * (c * u - sn * v), s * (sn * u + c * v));
        }
      r.at<float>(y, x) = static_cast<float>(sum / 16);
    }
  return r;
}

double angleDiffMod(double a, double b, double period) {
  double d = std::fmod(a - b, period);
  if (d < -period / 2) d += period;
  if (d > period / 2) d -= period;
  return d;
}

// Gaussian-blurred white noise: a pattern with no period.
cv::Mat noiseRaster(int M, double sigma, uint64_t seed) {
  Rng rng(seed);
  cv::Mat r(M, M, CV_32F);
  for (int y = 0; y < M; ++y)
    for (int x = 0; x < M; ++x) r.at<float>(y, x) = rng.normal();
  cv::GaussianBlur(r, r, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
  return r;
}

cv::Mat diskWeight(int M) {
  cv::Mat weight(M, M, CV_32F, cv::Scalar(0));
  cv::circle(weight, {M / 2, M / 2}, M / 2 - 4, cv::Scalar(1), cv::FILLED);
  cv::GaussianBlur(weight, weight, cv::Size(0, 0), 4.0);
  return weight;
}

// The photo raster shows the pattern at 20 known similarities (scale 0.5x to 1.5x, rotations
// over half a turn), box-filtered per cell as a camera integrates; the graph raster holds two
// whole periods at a finer cell. The scale comes back within 6 % and the rotation within 1 degree
// modulo the checker's 90-degree symmetry.
TEST(Optim_UvSpectrum, recovers_scale_and_rotation_of_a_synthetic_raster) {
  const int M = 192;
  const double cell = 1.0 / 40;
  const cv::Mat weight = diskWeight(M);
  const double cellG = 2.0 / M;  // whole periods
  const cv::Mat graph = raster(M, cellG, 0.0, 0.0);
  double worstScale = 0, worstRot = 0, minResponse = 1;
  for (double ls : {-0.7, -0.3, 0.0, 0.4}) {
    for (double rotDeg : {0.0, 20.0, 35.0, 70.0, 125.0}) {
      const cv::Mat photo = raster(M, cell, ls, radians(rotDeg));
      const UvSpectrumEstimate e = estimateSimilarityBySpectrum(photo, weight, graph, cellG / cell);
      EXPECT_TRUE(e.ok) << ls << " " << rotDeg;
      worstScale = std::max(worstScale, std::abs(e.logScale - ls));
      worstRot = std::max(worstRot, std::abs(angleDiffMod(degrees(e.rotation), rotDeg, 90.0)));
      minResponse = std::min(minResponse, e.response);
    }
  }
  std::printf(
      "[   info   ] 20 similarities: worst |log-scale error| %.3f, worst rotation error %.2f deg "
      "(mod 90), lowest response %.3f\n",
      worstScale, worstRot, minResponse);
  EXPECT_LT(worstScale, 0.06);
  EXPECT_LT(worstRot, 1.0);
}

// A pattern without a period gives no clear alignment: ok is false, so the fit keeps its whole
// scale grid. Measured responses: periodic 0.38-0.43 (above), noise below minResponse.
TEST(Optim_UvSpectrum, aperiodic_patterns_are_not_trusted) {
  const int M = 192;
  const double cell = 1.0 / 40, cellG = 2.0 / M;
  const cv::Mat weight = diskWeight(M);
  double worst = -1;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const cv::Mat photo = noiseRaster(M, 1.5, seed), graphNoise = noiseRaster(M, 2.5, seed + 100);
    const UvSpectrumEstimate a =
        estimateSimilarityBySpectrum(photo, weight, graphNoise, cellG / cell);
    const UvSpectrumEstimate b =
        estimateSimilarityBySpectrum(photo, weight, raster(M, cellG, 0.0, 0.0), cellG / cell);
    std::printf("[   info   ] noise photo: response %.3f against noise, %.3f against the checker\n",
                a.response, b.response);
    EXPECT_FALSE(a.ok);
    EXPECT_FALSE(b.ok);
    worst = std::max({worst, a.response, b.response});
  }
  EXPECT_LT(worst, UvSpectrumOptions{}.minResponse);
}

// Degenerate inputs: no NaN, no throw, ok false.
TEST(Optim_UvSpectrum, degenerate_rasters_give_no_estimate) {
  const int M = 64;
  const cv::Mat zero = cv::Mat::zeros(M, M, CV_32F), ones(M, M, CV_32F, cv::Scalar(1));
  const cv::Mat pattern = raster(M, 2.0 / M, 0.0, 0.0);
  EXPECT_FALSE(estimateSimilarityBySpectrum(pattern, zero, pattern).ok);      // no data
  EXPECT_FALSE(estimateSimilarityBySpectrum(zero, ones, pattern).ok);         // black photo
  EXPECT_FALSE(estimateSimilarityBySpectrum(ones * 1e30, ones, pattern).ok);  // saturated, flat
  const UvSpectrumEstimate e = estimateSimilarityBySpectrum(pattern, ones, zero);  // flat graph
  EXPECT_FALSE(e.ok);
  EXPECT_TRUE(std::isfinite(e.logScale) && std::isfinite(e.rotation) && std::isfinite(e.response));
  cv::Mat tiny = cv::Mat::ones(8, 8, CV_32F);
  EXPECT_FALSE(estimateSimilarityBySpectrum(tiny, tiny, tiny).ok);
  EXPECT_THROW(estimateSimilarityBySpectrum(pattern, ones, cv::Mat::zeros(M, M + 1, CV_32F)),
               Exception);
}

}  // namespace
}  // namespace ps

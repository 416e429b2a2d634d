#include "photoscene/eval/texture_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/color.hpp"

namespace ps::eval {

namespace {

constexpr std::array<int, 3> kLbpRadii = {1, 2, 4};
constexpr int kLbpPoints = 8;
constexpr int kLbpBins = kLbpPoints + 2;
constexpr int kRadialBins = 6, kAngularBins = 4;
constexpr double kMinFrequency = 1.0 / 64.0, kMaxFrequency = 0.5;
constexpr int kContrastBins = 16;
constexpr double kContrastMax = 2.5;
constexpr double kTinyMean = 1e-12;

/// Luminance of a linear RGB image, NaN and negative values set to 0.
cv::Mat luminance(const cv::Mat& image) {
  cv::Mat y(image.size(), CV_32FC1);
  for (int r = 0; r < image.rows; ++r) {
    const cv::Vec3f* p = image.ptr<cv::Vec3f>(r);
    float* q = y.ptr<float>(r);
    for (int c = 0; c < image.cols; ++c) {
      const float v = ps::luminance(p[c]);
      q[c] = std::isfinite(v) && v > 0 ? v : 0.0f;
    }
  }
  return y;
}

void normalise(std::vector<double>& h) {
  double s = 0;
  for (double v : h) s += v;
  if (s > 0)
    for (double& v : h) v /= s;
}

float bilinear(const cv::Mat& img, float x, float y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const int x1 = std::min(x0 + 1, img.cols - 1), y1 = std::min(y0 + 1, img.rows - 1);
  const float fx = x - x0, fy = y - y0;
  const float a = img.at<float>(y0, x0), b = img.at<float>(y0, x1);
  const float c = img.at<float>(y1, x0), d = img.at<float>(y1, x1);
  return (a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy;
}

/// LBP^riu2 histogram (P = 8) at `radius` over the masked pixels whose circle is inside the image.
std::vector<double> lbpHistogram(const cv::Mat& y, const cv::Mat& mask, int radius) {
  cv::Mat s;
  const double sigma = 0.5 * radius;
  cv::GaussianBlur(y, s, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
  std::array<float, kLbpPoints> dx{}, dy{};
  for (int p = 0; p < kLbpPoints; ++p) {
    const double a = 2.0 * std::numbers::pi * p / kLbpPoints;
    dx[p] = static_cast<float>(radius * std::cos(a));
    dy[p] = static_cast<float>(-radius * std::sin(a));
    if (std::abs(dx[p]) < 1e-6f) dx[p] = 0;
    if (std::abs(dy[p]) < 1e-6f) dy[p] = 0;
  }
  std::vector<double> h(kLbpBins, 0.0);
  for (int r = radius; r < y.rows - radius; ++r) {
    const uint8_t* m = mask.ptr<uint8_t>(r);
    for (int c = radius; c < y.cols - radius; ++c) {
      if (!m[c]) continue;
      // a relative tolerance: bilinear weights of a constant neighbourhood must not flip bits
      const float g = s.at<float>(r, c) - 1e-5f * std::abs(s.at<float>(r, c));
      std::array<int, kLbpPoints> bit{};
      int ones = 0;
      for (int p = 0; p < kLbpPoints; ++p) {
        bit[p] = bilinear(s, c + dx[p], r + dy[p]) >= g ? 1 : 0;
        ones += bit[p];
      }
      int transitions = 0;
      for (int p = 0; p < kLbpPoints; ++p) transitions += bit[p] != bit[(p + 1) % kLbpPoints];
      h[transitions <= 2 ? ones : kLbpPoints + 1] += 1;
    }
  }
  normalise(h);
  return h;
}

/// Fractions of the windowed, mean-normalised region's power in radial x orientation bins.
std::vector<double> spectrumHistogram(const cv::Mat& y, const cv::Mat& mask, double mean) {
  std::vector<double> h(kRadialBins * kAngularBins, 0.0);
  const cv::Rect box = cv::boundingRect(mask);
  if (box.width < 2 || box.height < 2 || mean <= kTinyMean) return h;
  cv::Mat window;
  cv::createHanningWindow(window, box.size(), CV_32F);
  const int n = cv::getOptimalDFTSize(std::max({box.width, box.height, 8}));
  cv::Mat v = cv::Mat::zeros(n, n, CV_32FC1);
  for (int r = 0; r < box.height; ++r)
    for (int c = 0; c < box.width; ++c)
      if (mask.at<uint8_t>(box.y + r, box.x + c))
        v.at<float>(r, c) = static_cast<float>((y.at<float>(box.y + r, box.x + c) / mean - 1.0) *
                                               window.at<float>(r, c));
  cv::Mat f;
  cv::dft(v, f, cv::DFT_COMPLEX_OUTPUT);
  const double logMin = std::log(kMinFrequency), logSpan = std::log(kMaxFrequency) - logMin;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double fy = (r < (n + 1) / 2 ? r : r - n) / static_cast<double>(n);
      const double fx = (c < (n + 1) / 2 ? c : c - n) / static_cast<double>(n);
      const double radius = std::hypot(fx, fy);
      if (radius < kMinFrequency || radius > kMaxFrequency) continue;
      int rb = static_cast<int>((std::log(radius) - logMin) / logSpan * kRadialBins);
      rb = std::clamp(rb, 0, kRadialBins - 1);
      double angle = std::atan2(fy, fx);
      if (angle < 0) angle += std::numbers::pi;
      int ab =
          static_cast<int>(std::floor((angle + std::numbers::pi / 8) / (std::numbers::pi / 4)));
      ab %= kAngularBins;
      const cv::Vec2f z = f.at<cv::Vec2f>(r, c);
      h[rb * kAngularBins + ab] +=
          static_cast<double>(z[0]) * z[0] + static_cast<double>(z[1]) * z[1];
    }
  for (double& x : h)
    if (!std::isfinite(x)) x = 0;
  normalise(h);
  return h;
}

std::vector<double> contrastHistogram(const cv::Mat& y, const cv::Mat& mask, double mean) {
  std::vector<double> h(kContrastBins, 0.0);
  for (int r = 0; r < y.rows; ++r) {
    const uint8_t* m = mask.ptr<uint8_t>(r);
    const float* p = y.ptr<float>(r);
    for (int c = 0; c < y.cols; ++c) {
      if (!m[c]) continue;
      // a black region is a constant one: every pixel at the mean
      const double ratio = mean > kTinyMean ? p[c] / mean : 1.0;
      const int b =
          std::clamp(static_cast<int>(ratio / kContrastMax * kContrastBins), 0, kContrastBins - 1);
      h[b] += 1;
    }
  }
  normalise(h);
  return h;
}

}  // namespace

TextureHistograms textureHistograms(const cv::Mat& image, const cv::Mat& mask) {
  checkImage(image, CV_32FC3, "textureHistograms image");
  checkImage(mask, CV_8UC1, image.size(), "textureHistograms mask");
  TextureHistograms t;
  t.pixels = cv::countNonZero(mask);
  PS_Check(t.pixels > 0, "textureHistograms: the mask has no pixel");
  const cv::Mat y = luminance(image);
  const double mean = cv::mean(y, mask)[0];
  for (int radius : kLbpRadii) t.lbp.push_back(lbpHistogram(y, mask, radius));
  t.spectrum = spectrumHistogram(y, mask, mean);
  t.contrast = contrastHistogram(y, mask, mean);
  return t;
}

double chiSquare(const std::vector<double>& a, const std::vector<double>& b) {
  PS_CheckEQ(a.size(), b.size(), "chiSquare: histograms of different lengths");
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double s = a[i] + b[i];
    if (s > 0) d += (a[i] - b[i]) * (a[i] - b[i]) / s;
  }
  return 0.5 * d;
}

TextureDistance textureDistance(const TextureHistograms& a, const TextureHistograms& b) {
  PS_CheckEQ(a.lbp.size(), b.lbp.size(), "textureDistance: LBP radii differ");
  TextureDistance d;
  for (size_t i = 0; i < a.lbp.size(); ++i) d.lbp += chiSquare(a.lbp[i], b.lbp[i]);
  if (!a.lbp.empty()) d.lbp /= static_cast<double>(a.lbp.size());
  d.spectrum = chiSquare(a.spectrum, b.spectrum);
  d.contrast = chiSquare(a.contrast, b.contrast);
  d.total = (d.lbp + d.spectrum + d.contrast) / 3.0;
  return d;
}

TextureDistance textureDistance(const cv::Mat& imageA, const cv::Mat& maskA, const cv::Mat& imageB,
                                const cv::Mat& maskB) {
  return textureDistance(textureHistograms(imageA, maskA), textureHistograms(imageB, maskB));
}

}  // namespace ps::eval

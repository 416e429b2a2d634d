#include "photoscene/features/texture_pixel.hpp"

#include <algorithm>
#include <cmath>

#include "photoscene/core/color.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "gradient_check.hpp"

namespace ps {

namespace {

constexpr int kPixelBorder = 3;           // Omega: pixels at least this far from the border
constexpr double kPixelMeanFloor = 1e-6;  // mu's floor (linear luminance)
constexpr double kPixelContrastEps = 1e-3;
constexpr int kPixelEntries = 1 + PixelStructure::kLags;

// The forward pass with what the backward pass needs.
struct PixelPass {
  cv::Mat y, a;  // luminance; centred residual A (CV_64FC1; 0 on the outer ring)
  double mu = 0, v = 0;
  std::array<double, PixelStructure::kLags> cov{};
  int omega = 0;
  PixelStructure s;
};

PixelPass pixelForward(const cv::Mat& image, double delta) {
  checkImage(image, CV_32FC3, "pixelStructure image");
  PixelPass p;
  const int h = image.rows, w = image.cols;
  if (h < 2 * kPixelBorder + 1 || w < 2 * kPixelBorder + 1) return p;
  p.y.create(h, w, CV_64FC1);
  double sum = 0;
  for (int r = 0; r < h; ++r) {
    const cv::Vec3f* in = image.ptr<cv::Vec3f>(r);
    double* out = p.y.ptr<double>(r);
    for (int c = 0; c < w; ++c)
      sum += out[c] = luminance(double(in[c][0]), double(in[c][1]), double(in[c][2]));
  }
  p.s.mean = sum / (double(h) * w);
  p.mu = std::max(kPixelMeanFloor, p.s.mean);
  p.a = cv::Mat::zeros(h, w, CV_64FC1);
  for (int r = 1; r < h - 1; ++r)
    for (int c = 1; c < w - 1; ++c) {
      double box = 0;
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) box += p.y.at<double>(r + j, c + i);
      p.a.at<double>(r, c) = p.y.at<double>(r, c) - box / 9;
    }
  double m = 0;
  for (int r = kPixelBorder; r < h - kPixelBorder; ++r)
    for (int c = kPixelBorder; c < w - kPixelBorder; ++c) m += p.a.at<double>(r, c), ++p.omega;
  m /= p.omega;
  for (int r = 1; r < h - 1; ++r)
    for (int c = 1; c < w - 1; ++c) p.a.at<double>(r, c) -= m;
  double v = 0;
  for (int r = kPixelBorder; r < h - kPixelBorder; ++r)
    for (int c = kPixelBorder; c < w - kPixelBorder; ++c) {
      const double a = p.a.at<double>(r, c);
      v += a * a;
      for (int d = 0; d < PixelStructure::kLags; ++d)
        p.cov[d] +=
            a * p.a.at<double>(r + PixelStructure::kLag[d][1], c + PixelStructure::kLag[d][0]);
    }
  p.v = v / p.omega + delta + 1e-20;
  for (double& c : p.cov) c /= p.omega;
  p.s.contrast = std::sqrt(p.v) / p.mu;
  for (int d = 0; d < PixelStructure::kLags; ++d) p.s.correlation[d] = p.cov[d] / p.v;
  p.s.pixels = p.omega;
  return p;
}

}  // namespace

PixelStructure pixelStructure(const cv::Mat& image) {
  return pixelForward(image, 0.0).s;
}

double pixelStructureLoss(const cv::Mat& image, const PixelStructure& target, double weight,
                          cv::Mat* grad) {
  const double delta = 1e-6 * target.mean * target.mean;
  const PixelPass p = pixelForward(image, delta);
  if (p.omega == 0) return 0.0;
  const PixelStructure& s = p.s;
  const double k = weight / kPixelEntries;
  const double lc =
      std::log((s.contrast + kPixelContrastEps) / (target.contrast + kPixelContrastEps));
  double loss = lc * lc;
  for (int d = 0; d < PixelStructure::kLags; ++d)
    loss += (s.correlation[d] - target.correlation[d]) * (s.correlation[d] - target.correlation[d]);
  loss *= k;
  if (!grad) return loss;

  // contrast = sqrt(v) / mu, correlation_d = cov_d / v
  const double gContrast = k * 2 * lc / (s.contrast + kPixelContrastEps);
  const double sv = std::sqrt(p.v);
  double gv = gContrast * 0.5 / (sv * p.mu);
  std::array<double, PixelStructure::kLags> gCov{};
  for (int d = 0; d < PixelStructure::kLags; ++d) {
    const double gCorr = k * 2 * (s.correlation[d] - target.correlation[d]);
    gCov[d] = gCorr / p.v;
    gv -= gCorr * p.cov[d] / (p.v * p.v);
  }
  const double gMu = s.mean > kPixelMeanFloor ? -gContrast * sv / (p.mu * p.mu) : 0.0;
  const int h = image.rows, w = image.cols;
  // through v and cov_d to A
  cv::Mat gA = cv::Mat::zeros(h, w, CV_64FC1);
  for (int r = kPixelBorder; r < h - kPixelBorder; ++r)
    for (int c = kPixelBorder; c < w - kPixelBorder; ++c) {
      const double a = p.a.at<double>(r, c);
      double& g = gA.at<double>(r, c);
      g += gv * 2 * a / p.omega;
      for (int d = 0; d < PixelStructure::kLags; ++d) {
        const int rr = r + PixelStructure::kLag[d][1], cc = c + PixelStructure::kLag[d][0];
        g += gCov[d] * p.a.at<double>(rr, cc) / p.omega;
        gA.at<double>(rr, cc) += gCov[d] * a / p.omega;
      }
    }
  // A = R - mean_Omega(R) on the residual's pixels
  double gSum = 0;
  for (int r = 1; r < h - 1; ++r)
    for (int c = 1; c < w - 1; ++c) gSum += gA.at<double>(r, c);
  for (int r = kPixelBorder; r < h - kPixelBorder; ++r)
    for (int c = kPixelBorder; c < w - kPixelBorder; ++c) gA.at<double>(r, c) -= gSum / p.omega;
  // R = Y - box3(Y), and mu = mean(Y)
  cv::Mat gY(h, w, CV_64FC1, cv::Scalar(gMu / (double(h) * w)));
  for (int r = 1; r < h - 1; ++r)
    for (int c = 1; c < w - 1; ++c) {
      const double g = gA.at<double>(r, c);
      if (g == 0) continue;
      gY.at<double>(r, c) += g;
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) gY.at<double>(r + j, c + i) -= g / 9;
    }
  if (grad->empty()) *grad = cv::Mat::zeros(h, w, CV_32FC3);
  checkImage(*grad, CV_32FC3, image.size(), "pixelStructureLoss gradient");
  for (int r = 0; r < h; ++r) {
    const double* gy = gY.ptr<double>(r);
    cv::Vec3f* out = grad->ptr<cv::Vec3f>(r);
    for (int c = 0; c < w; ++c)
      for (int q = 0; q < 3; ++q) out[c][q] += float(gy[c] * kLuminanceWeights[q]);
  }
  return loss;
}

TextureLossGradientCheck checkPixelStructureGradient(const cv::Mat& image,
                                                     const PixelStructure& target, double weight,
                                                     const std::vector<cv::Point>& pixels,
                                                     double step) {
  cv::Mat grad;
  pixelStructureLoss(image, target, weight, &grad);
  if (grad.empty()) grad = cv::Mat::zeros(image.size(), CV_32FC3);
  return checkImageGradient(image, grad, pixels, step, [&](const cv::Mat& x) {
    return pixelStructureLoss(x, target, weight);
  });
}

}  // namespace ps

// Procedural textures and masks for the features tests (linear RGB, CV_32FC3).
#pragma once

#include "photoscene/core/rng.hpp"
#include "photoscene/features/texture_loss.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace ps::test {

/// The texture loss of `render` against `target`; `grad` gets its gradient (d loss / d render).
inline double lossAndGradient(const TextureLossTarget& target, const cv::Mat& render,
                              cv::Mat& grad) {
  TextureLossParams p;
  p.target = &target;
  p.render = render;
  const double loss = textureLossForward(p);
  textureLossBackward(p, 1.0f, grad);
  return loss;
}

/// The image under a light of another colour and level: each channel times its factor.
inline cv::Mat scaleChannels(const cv::Mat& img, cv::Vec3f s) {
  cv::Mat out;
  cv::multiply(img, cv::Scalar(s[0], s[1], s[2]), out);
  return out;
}

/// A sinusoidal grating: period in pixels, angle in degrees (x right, y down), mean 0.4.
inline cv::Mat stripes(cv::Size size, double period, double angleDeg, double phase = 0.0,
                       cv::Vec3f tint = {1.0f, 0.9f, 0.8f}) {
  cv::Mat img(size, CV_32FC3);
  const double a = angleDeg * CV_PI / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const double v = 0.4 + 0.25 * std::cos(2.0 * CV_PI * (x * c + y * s) / period + phase);
      img.at<cv::Vec3f>(y, x) = tint * static_cast<float>(v);
    }
  return img;
}

/// A checkerboard of square cells (0.2 / 0.6), shifted by `offset` pixels.
inline cv::Mat checker(cv::Size size, int cell, cv::Point offset = {0, 0},
                       cv::Vec3f tint = {0.9f, 1.0f, 0.8f}) {
  cv::Mat img(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const int cx = (x + offset.x) / cell, cy = (y + offset.y) / cell;
      img.at<cv::Vec3f>(y, x) = tint * (((cx + cy) & 1) ? 0.6f : 0.2f);
    }
  return img;
}

/// Gaussian-filtered white noise (blur sigma in pixels sets the grain), mean 0.4, std 0.12.
inline cv::Mat noise(cv::Size size, double blurSigma, uint64_t seed,
                     cv::Vec3f tint = {0.8f, 0.85f, 1.0f}) {
  ps::Rng rng(seed);
  cv::Mat n(size, CV_32F);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) n.at<float>(y, x) = rng.normal();
  cv::GaussianBlur(n, n, cv::Size(0, 0), blurSigma, blurSigma, cv::BORDER_REFLECT);
  cv::Scalar mean, sd;
  cv::meanStdDev(n, mean, sd);
  n = (n - mean[0]) * (0.12 / sd[0]) + 0.4;
  cv::Mat img(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) img.at<cv::Vec3f>(y, x) = tint * n.at<float>(y, x);
  return img;
}

inline cv::Mat diskMask(cv::Size size, cv::Point center, int radius) {
  cv::Mat m = cv::Mat::zeros(size, CV_8UC1);
  cv::circle(m, center, radius, cv::Scalar(255), cv::FILLED);
  return m;
}

/// A disk of about 20k pixels centered in a 320 x 240 image (radius 80: 20,100 pixels).
inline cv::Mat partMask320() {
  return diskMask({320, 240}, {160, 120}, 80);
}

/// `count` random pixels (seeded) inside (`inside`) or outside a CV_8UC1 mask, repeats allowed:
/// where the gradient checks probe.
inline std::vector<cv::Point> randomPixels(const cv::Mat& mask, bool inside, int count,
                                           uint64_t seed) {
  ps::Rng rng(seed);
  std::vector<cv::Point> out;
  while (static_cast<int>(out.size()) < count) {
    const cv::Point p(rng.uniformInt(mask.cols), rng.uniformInt(mask.rows));
    if ((mask.at<uint8_t>(p) != 0) == inside) out.push_back(p);
  }
  return out;
}

}  // namespace ps::test

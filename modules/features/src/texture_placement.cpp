#include "photoscene/features/texture_placement.hpp"

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "gradient_check.hpp"
#include "photoscene/core/color.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace ps {

namespace {

constexpr const double* kLum = kLuminanceWeights;
constexpr int kBorder = cv::BORDER_CONSTANT | cv::BORDER_ISOLATED;

int kernelRadius(double sigma) {
  return std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
}

// Gaussian low-pass with zero border (CV_64F); symmetric, so its own adjoint.
cv::Mat lowpass(const cv::Mat& src, double sigma) {
  const int r = kernelRadius(sigma);
  const cv::Mat k = cv::getGaussianKernel(2 * r + 1, sigma, CV_64F);
  cv::Mat out;
  cv::sepFilter2D(src, out, CV_64F, k, k, cv::Point(-1, -1), 0.0, kBorder);
  return out;
}

// Masked luminance of the crop (CV_64F, 0 outside the mask).
cv::Mat maskedLuminance(const cv::Mat& image, const cv::Rect& crop, const cv::Mat& mask) {
  cv::Mat l(crop.size(), CV_64F);
  for (int y = 0; y < crop.height; ++y) {
    const cv::Vec3f* c = image.ptr<cv::Vec3f>(crop.y + y) + crop.x;
    const float* m = mask.ptr<float>(y);
    double* d = l.ptr<double>(y);
    for (int x = 0; x < crop.width; ++x)
      d[x] = m[x] != 0.0f ? kLum[0] * c[x][0] + kLum[1] * c[x][1] + kLum[2] * c[x][2] : 0.0;
  }
  return l;
}

}  // namespace

bool PlacementLossOptions::IsValid(std::string* error) const {
  std::string msg;
  if (!(sigma >= 0.5 && sigma <= 32.0))
    msg = "placement sigma must be in [0.5, 32] pixels, got " + std::to_string(sigma);
  if (error) *error = msg;
  return msg.empty();
}

PlacementLossTarget::PlacementLossTarget(const cv::Mat& photo, const cv::Mat& mask,
                                         const PlacementLossOptions& options)
    : options_(options), size_(photo.size()) {
  std::string err;
  PS_Check(options.IsValid(&err), "invalid PlacementLossOptions: " << err);
  checkImage(photo, CV_32FC3, "placement loss photo");
  checkImage(mask, CV_8UC1, photo.size(), "placement loss mask");
  PS_Check(allFinite(photo), "placement loss photo has NaN or Inf values");
  const cv::Rect box = cv::boundingRect(mask);
  count_ = cv::countNonZero(mask);
  PS_Check(count_ > 0 && box.area() > 0, "placement loss: the mask is empty");
  // the crop is the box: outside it M L and M are 0, and the low-pass is read on the mask only
  crop_ = box;
  mask_.create(box.size(), CV_32F);
  for (int y = 0; y < box.height; ++y) {
    const uint8_t* s = mask.ptr<uint8_t>(box.y + y) + box.x;
    float* d = mask_.ptr<float>(y);
    for (int x = 0; x < box.width; ++x) d[x] = s[x] ? 1.0f : 0.0f;
  }
  cv::Mat m64;
  mask_.convertTo(m64, CV_64F);
  const cv::Mat cover = lowpass(m64, options.sigma);
  invCoverage_ = cv::Mat::zeros(box.size(), CV_64F);
  for (int y = 0; y < box.height; ++y)
    for (int x = 0; x < box.width; ++x)
      if (mask_.at<float>(y, x) != 0.0f)  // a mask pixel's own weight keeps G(M) > 0
        invCoverage_.at<double>(y, x) = 1.0 / std::max(cover.at<double>(y, x), 1e-300);
  const cv::Mat l = maskedLuminance(photo, crop_, mask_);
  const cv::Mat b = lowpass(l, options.sigma).mul(invCoverage_);
  const double n = count_;
  const double meanL = cv::sum(l)[0] / n;
  eps_ = 1e-3 * std::max(meanL, 1e-6);
  const double mean = cv::sum(b)[0] / n;  // b is 0 off the mask
  cv::Mat c = b - mean;
  c = c.mul(m64);
  const double sd = std::sqrt(c.dot(c) / n + eps_ * eps_);
  photoHat_ = c / sd;
}

double placementLoss(const PlacementLossTarget& t, const cv::Mat& render, cv::Mat* grad,
                     float gradScale, bool accumulate) {
  checkImage(render, CV_32FC3, t.size_, "placement loss render");
  PS_Check(allFinite(render(t.crop_)), "placement loss render has NaN or Inf values");
  const double sigma = t.options_.sigma;
  cv::Mat m64;
  t.mask_.convertTo(m64, CV_64F);
  const cv::Mat l = maskedLuminance(render, t.crop_, t.mask_);
  const cv::Mat b = lowpass(l, sigma).mul(t.invCoverage_);
  const double n = t.count_;
  const double mean = cv::sum(b)[0] / n;
  const cv::Mat c = (b - mean).mul(m64);
  const double var = c.dot(c) / n + t.eps_ * t.eps_;
  const double sd = std::sqrt(var);
  const double rho = c.dot(t.photoHat_) / (n * sd);
  const double loss = 1.0 - rho;
  if (!grad) return loss;
  // d loss / d c = -(photoHat / (n sd) - rho c / (n var)) on the mask; centering's adjoint
  // subtracts the mean over the mask; then b = G(M L) / G(M): g_L = M G(g_b / G(M)).
  cv::Mat gc = (c * (rho / (n * var)) - t.photoHat_ * (1.0 / (n * sd))) * gradScale;
  const double gMean = cv::sum(gc)[0] / n;
  cv::Mat gb = (gc - gMean).mul(m64);
  const cv::Mat gl = lowpass(gb.mul(t.invCoverage_), sigma).mul(m64);
  const bool reuse = accumulate && grad->type() == CV_32FC3 && grad->size() == t.size_;
  if (!reuse) {
    grad->create(t.size_, CV_32FC3);
    grad->setTo(cv::Scalar::all(0));
  }
  for (int y = 0; y < t.crop_.height; ++y) {
    const double* g = gl.ptr<double>(y);
    cv::Vec3f* out = grad->ptr<cv::Vec3f>(t.crop_.y + y) + t.crop_.x;
    for (int x = 0; x < t.crop_.width; ++x)
      for (int ch = 0; ch < 3; ++ch) out[x][ch] += static_cast<float>(kLum[ch] * g[x]);
  }
  return loss;
}

TextureLossGradientCheck checkPlacementLossGradient(const PlacementLossTarget& target,
                                                    const cv::Mat& render,
                                                    const std::vector<cv::Point>& pixels,
                                                    double step) {
  cv::Mat grad;
  placementLoss(target, render, &grad);
  return checkImageGradient(render, grad, pixels, step,
                            [&](const cv::Mat& image) { return placementLoss(target, image); });
}

}  // namespace ps

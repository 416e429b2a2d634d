#include "photoscene/features/texture_contrast.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "photoscene/core/color.hpp"
#include "photoscene/core/error.hpp"

namespace ps {

namespace {
/// The q-quantile of v (nearest rank; reorders v). v must not be empty.
double quantile(std::vector<double>& v, double q) {
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(i), v.end());
  return v[i];
}
}  // namespace

LocalContrast typicalLocalContrast(const cv::Mat& image, const cv::Mat& mask,
                                   const LocalContrastOptions& options) {
  PS_Check(image.type() == CV_32FC3, "typicalLocalContrast: image must be CV_32FC3");
  PS_Check(mask.type() == CV_8UC1 && mask.size() == image.size(),
           "typicalLocalContrast: mask must be CV_8UC1 of the image's size");
  PS_Check(options.radius >= 1 && options.darkFloor > 0 && options.scale >= 1,
           "typicalLocalContrast: radius must be >= 1, darkFloor > 0 and scale >= 1");
  LocalContrast out;
  if (cv::countNonZero(mask) == 0) return out;
  cv::Mat lum(image.size(), CV_32F);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const float l = luminance(image.at<cv::Vec3f>(y, x));
      lum.at<float>(y, x) = std::isfinite(l) && l > 0 ? l : 0.0f;
    }
  cv::Mat region = mask;
  if (options.scale > 1) {
    // box means over scale x scale cells; a cell counts when all its pixels are in the mask
    const int s = options.scale, w = image.cols / s, h = image.rows / s;
    if (w == 0 || h == 0) return out;
    const cv::Rect crop(0, 0, w * s, h * s);
    cv::Mat coarse, cover, in01;
    cv::resize(lum(crop), coarse, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    cv::Mat(mask(crop) != 0).convertTo(in01, CV_32F, 1.0 / 255.0);
    cv::resize(in01, cover, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    lum = coarse;
    region = cover > 1.0f - 0.5f / static_cast<float>(s * s);
    if (cv::countNonZero(region) == 0) return out;
  }
  const int k = 2 * options.radius + 1;
  cv::Mat inside;
  cv::erode(region, inside, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)), cv::Point(-1, -1),
            1, cv::BORDER_CONSTANT, cv::Scalar(0));
  const int n = cv::countNonZero(inside);
  if (n == 0) return out;
  const double regionMean = cv::mean(lum, region)[0];
  const double floor = std::max(1e-8, options.darkFloor * regionMean);
  cv::Mat mu, mu2;
  cv::blur(lum, mu, cv::Size(k, k), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::blur(lum.mul(lum), mu2, cv::Size(k, k), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  std::vector<double> c;
  c.reserve(n);
  for (int y = 0; y < lum.rows; ++y)
    for (int x = 0; x < lum.cols; ++x)
      if (inside.at<uint8_t>(y, x)) {
        const double m = mu.at<float>(y, x);
        const double var = std::max(0.0, static_cast<double>(mu2.at<float>(y, x)) - m * m);
        c.push_back(std::sqrt(var) / std::max(m, floor));
      }
  out.pixels = n;
  out.q25 = quantile(c, 0.25);
  out.median = quantile(c, 0.5);
  out.q75 = quantile(c, 0.75);
  return out;
}

ChromaSpread chromaSpread(const cv::Mat& image, const cv::Mat& mask, float darkFloor) {
  PS_Check(image.type() == CV_32FC3, "chromaSpread: image must be CV_32FC3");
  PS_Check(mask.type() == CV_8UC1 && mask.size() == image.size(),
           "chromaSpread: mask must be CV_8UC1 of the image's size");
  PS_Check(darkFloor >= 0, "chromaSpread: darkFloor must be >= 0");
  ChromaSpread out;
  std::vector<cv::Vec3f> px;
  std::vector<float> lum;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      if (!mask.at<uint8_t>(y, x)) continue;
      const cv::Vec3f v = image.at<cv::Vec3f>(y, x);
      bool ok = true;
      for (int c = 0; c < 3; ++c) ok = ok && std::isfinite(v[c]) && v[c] >= 0;
      if (!ok) continue;
      px.push_back(v);
      lum.push_back(luminance(v));
    }
  if (px.empty()) return out;
  std::vector<float> sorted = lum;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (!(median > 0)) return out;
  const double eps = 0.01 * median, floor = darkFloor * median;
  std::vector<double> rg, bg;
  for (size_t i = 0; i < px.size(); ++i) {
    if (lum[i] < floor) continue;
    rg.push_back(std::log((px[i][0] + eps) / (px[i][1] + eps)));
    bg.push_back(std::log((px[i][2] + eps) / (px[i][1] + eps)));
  }
  if (rg.empty()) return out;
  auto range = [](std::vector<double>& v) { return quantile(v, 0.9) - quantile(v, 0.1); };
  out.pixels = static_cast<int>(rg.size());
  out.spread = std::hypot(range(rg), range(bg));
  return out;
}

}  // namespace ps

#include "photoscene/features/texture_contrast.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "photoscene/core/color.hpp"
#include "photoscene/core/error.hpp"

namespace ps {

LocalContrast typicalLocalContrast(const cv::Mat& image, const cv::Mat& mask,
                                   const LocalContrastOptions& options) {
  PS_Check(image.type() == CV_32FC3, "typicalLocalContrast: image must be CV_32FC3");
  PS_Check(mask.type() == CV_8UC1 && mask.size() == image.size(),
           "typicalLocalContrast: mask must be CV_8UC1 of the image's size");
  PS_Check(options.radius >= 1 && options.darkFloor > 0,
           "typicalLocalContrast: radius must be >= 1 and darkFloor > 0");
  LocalContrast out;
  if (cv::countNonZero(mask) == 0) return out;
  cv::Mat lum(image.size(), CV_32F);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const float l = luminance(image.at<cv::Vec3f>(y, x));
      lum.at<float>(y, x) = std::isfinite(l) && l > 0 ? l : 0.0f;
    }
  const int k = 2 * options.radius + 1;
  cv::Mat inside;
  cv::erode(mask, inside, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)), cv::Point(-1, -1),
            1, cv::BORDER_CONSTANT, cv::Scalar(0));
  const int n = cv::countNonZero(inside);
  if (n == 0) return out;
  const double regionMean = cv::mean(lum, mask)[0];
  const double floor = std::max(1e-8, options.darkFloor * regionMean);
  cv::Mat mu, mu2;
  cv::blur(lum, mu, cv::Size(k, k), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::blur(lum.mul(lum), mu2, cv::Size(k, k), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  std::vector<double> c;
  c.reserve(n);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      if (inside.at<uint8_t>(y, x)) {
        const double m = mu.at<float>(y, x);
        const double var = std::max(0.0, static_cast<double>(mu2.at<float>(y, x)) - m * m);
        c.push_back(std::sqrt(var) / std::max(m, floor));
      }
  auto quantile = [&](double q) {
    const size_t i = std::min(c.size() - 1, static_cast<size_t>(q * (c.size() - 1) + 0.5));
    std::nth_element(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(i), c.end());
    return c[i];
  };
  out.pixels = n;
  out.q25 = quantile(0.25);
  out.median = quantile(0.5);
  out.q75 = quantile(0.75);
  return out;
}

}  // namespace ps

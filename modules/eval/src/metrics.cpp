#include "photoscene/eval/metrics.hpp"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <opencv2/quality.hpp>

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"

namespace ps::eval {

namespace {
void checkPair(const cv::Mat& a, const cv::Mat& b) {
  checkImage(a, CV_32FC3, "metric input a");
  checkImage(b, CV_32FC3, b.size() == a.size() ? b.size() : a.size(), "metric input b");
}

double peak(ColorSpace s) { return s == ColorSpace::Srgb255 ? 255.0 : 1.0; }

/// Sum of squared differences and the number of (pixel, channel) terms under the mask.
std::pair<double, double> squaredError(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  double sum = 0, count = 0;
  for (int y = 0; y < a.rows; ++y) {
    const cv::Vec3f* pa = a.ptr<cv::Vec3f>(y);
    const cv::Vec3f* pb = b.ptr<cv::Vec3f>(y);
    const uint8_t* pm = mask.empty() ? nullptr : mask.ptr<uint8_t>(y);
    for (int x = 0; x < a.cols; ++x) {
      if (pm && !pm[x]) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = static_cast<double>(pa[x][c]) - pb[x][c];
        sum += d * d;
      }
      count += 3;
    }
  }
  return {sum, count};
}

cv::Mat luma(const cv::Mat& img) {
  // Rec. 601 luma (as GMSD's reference code uses on RGB)
  cv::Mat out(img.size(), CV_32FC1);
  for (int y = 0; y < img.rows; ++y) {
    const cv::Vec3f* p = img.ptr<cv::Vec3f>(y);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < img.cols; ++x) o[x] = 0.299f * p[x][0] + 0.587f * p[x][1] + 0.114f * p[x][2];
  }
  return out;
}
}  // namespace

std::string toString(ColorSpace space) { return space == ColorSpace::Srgb255 ? "srgb255" : "linear"; }

cv::Mat toMetricSpace(const cv::Mat& linearRgb, ColorSpace space) {
  checkImage(linearRgb, CV_32FC3, "metric input");
  if (space == ColorSpace::Linear) {
    cv::Mat clean = linearRgb.clone();
    cv::patchNaNs(clean, 0.0);
    return clean;
  }
  cv::Mat enc = linearToSrgb(linearRgb, CV_32F);  // clamps to [0, 1], NaN -> 0
  enc.convertTo(enc, CV_32F, 255.0);
  return enc;
}

double rmse(const cv::Mat& a, const cv::Mat& b, ColorSpace space, const cv::Mat& mask) {
  checkPair(a, b);
  if (!mask.empty()) checkImage(mask, CV_8UC1, a.size(), "metric mask");
  const auto [sum, count] = squaredError(toMetricSpace(a, space), toMetricSpace(b, space), mask);
  if (count == 0) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(sum / count);
}

double psnr(const cv::Mat& a, const cv::Mat& b, ColorSpace space, const cv::Mat& mask) {
  const double e = rmse(a, b, space, mask);
  if (std::isnan(e)) return e;
  if (e == 0) return std::numeric_limits<double>::infinity();
  return 20.0 * std::log10(peak(space) / e);
}

double ssim(const cv::Mat& a, const cv::Mat& b, ColorSpace space) {
  checkPair(a, b);
  // OpenCV's QualitySSIM assumes a dynamic range of 255; rescale linear values accordingly so
  // that the constants C1 = (0.01 L)^2, C2 = (0.03 L)^2 refer to the peak of the space.
  const double scale = 255.0 / peak(space);
  cv::Mat ma, mb;
  toMetricSpace(a, space).convertTo(ma, CV_32F, scale);
  toMetricSpace(b, space).convertTo(mb, CV_32F, scale);
  const cv::Scalar s = cv::quality::QualitySSIM::compute(ma, mb, cv::noArray());
  return (s[0] + s[1] + s[2]) / 3.0;
}

double gmsd(const cv::Mat& a, const cv::Mat& b, ColorSpace space) {
  checkPair(a, b);
  const double scale = 255.0 / peak(space);
  cv::Mat la, lb;
  luma(toMetricSpace(a, space)).convertTo(la, CV_32F, scale);
  luma(toMetricSpace(b, space)).convertTo(lb, CV_32F, scale);
  // 2x2 average, then every second pixel (the reference implementation's downsampling)
  auto down = [](const cv::Mat& m) {
    cv::Mat avg;
    cv::blur(m, avg, cv::Size(2, 2), cv::Point(0, 0), cv::BORDER_REFLECT);
    cv::Mat out((m.rows + 1) / 2, (m.cols + 1) / 2, CV_32FC1);
    for (int y = 0; y < out.rows; ++y)
      for (int x = 0; x < out.cols; ++x) out.at<float>(y, x) = avg.at<float>(2 * y, 2 * x);
    return out;
  };
  if (la.rows >= 4 && la.cols >= 4) {
    la = down(la);
    lb = down(lb);
  }
  const cv::Mat kx = (cv::Mat_<float>(3, 3) << 1, 0, -1, 1, 0, -1, 1, 0, -1) / 3.0f;
  const cv::Mat ky = kx.t();
  auto gradMag = [&](const cv::Mat& m) {
    cv::Mat gx, gy, mag;
    cv::filter2D(m, gx, CV_32F, kx, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
    cv::filter2D(m, gy, CV_32F, ky, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
    cv::magnitude(gx, gy, mag);
    return mag;
  };
  const cv::Mat ga = gradMag(la), gb = gradMag(lb);
  const double c = 170.0;
  double sum = 0, sum2 = 0;
  const double n = static_cast<double>(ga.total());
  for (int y = 0; y < ga.rows; ++y) {
    const float* pa = ga.ptr<float>(y);
    const float* pb = gb.ptr<float>(y);
    for (int x = 0; x < ga.cols; ++x) {
      const double gms = (2.0 * pa[x] * pb[x] + c) / (double(pa[x]) * pa[x] + double(pb[x]) * pb[x] + c);
      sum += gms;
      sum2 += gms * gms;
    }
  }
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

ImageMetrics compareImages(const cv::Mat& render, const cv::Mat& photo, ColorSpace space) {
  ImageMetrics m;
  m.space = space;
  m.rmse = rmse(render, photo, space);
  m.psnr = psnr(render, photo, space);
  m.ssim = ssim(render, photo, space);
  m.gmsd = gmsd(render, photo, space);
  return m;
}

}  // namespace ps::eval

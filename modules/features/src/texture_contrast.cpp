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

namespace {
/// Log-chromaticities (log R/G, log B/G) of the counted pixels (see chromaSpread).
std::vector<cv::Vec2d> logChromaticities(const cv::Mat& image, const cv::Mat& mask, float darkFloor,
                                         const char* who) {
  PS_Check(image.type() == CV_32FC3, who << ": image must be CV_32FC3");
  PS_Check(mask.type() == CV_8UC1 && mask.size() == image.size(),
           who << ": mask must be CV_8UC1 of the image's size");
  PS_Check(darkFloor >= 0, who << ": darkFloor must be >= 0");
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
  std::vector<cv::Vec2d> out;
  if (px.empty()) return out;
  std::vector<float> sorted = lum;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (!(median > 0)) return out;
  const double eps = 0.01 * median, floor = darkFloor * median;
  for (size_t i = 0; i < px.size(); ++i) {
    if (lum[i] < floor) continue;
    out.push_back({std::log((px[i][0] + eps) / (px[i][1] + eps)),
                   std::log((px[i][2] + eps) / (px[i][1] + eps))});
  }
  return out;
}

/// c minus the median of each coordinate.
void centreOnMedian(std::vector<cv::Vec2d>& c) {
  if (c.empty()) return;
  for (int k = 0; k < 2; ++k) {
    std::vector<double> v;
    v.reserve(c.size());
    for (const cv::Vec2d& p : c) v.push_back(p[k]);
    const double m = quantile(v, 0.5);
    for (cv::Vec2d& p : c) p[k] -= m;
  }
}

int64_t binKey(int64_t x, int64_t y) {
  return (x + (int64_t{1} << 30)) * (int64_t{1} << 32) + (y + (int64_t{1} << 30));
}
int64_t binOf(double v, double cell) {
  return static_cast<int64_t>(std::floor(std::clamp(v / cell, -1e6, 1e6)));
}
}  // namespace

ChromaSpread chromaSpread(const cv::Mat& image, const cv::Mat& mask, float darkFloor) {
  const std::vector<cv::Vec2d> c = logChromaticities(image, mask, darkFloor, "chromaSpread");
  ChromaSpread out;
  if (c.empty()) return out;
  std::vector<double> rg, bg;
  for (const cv::Vec2d& p : c) {
    rg.push_back(p[0]);
    bg.push_back(p[1]);
  }
  auto range = [](std::vector<double>& v) { return quantile(v, 0.9) - quantile(v, 0.1); };
  out.pixels = static_cast<int>(c.size());
  out.spread = std::hypot(range(rg), range(bg));
  return out;
}

bool ChromaGamut::contains(double rg, double bg) const {
  return std::binary_search(bins.begin(), bins.end(), binKey(binOf(rg, cell), binOf(bg, cell)));
}

ChromaGamut chromaGamut(const cv::Mat& image, const cv::Mat& mask, float darkFloor, double cell) {
  PS_Check(cell > 0, "chromaGamut: cell must be > 0");
  std::vector<cv::Vec2d> c = logChromaticities(image, mask, darkFloor, "chromaGamut");
  centreOnMedian(c);
  ChromaGamut g;
  g.cell = cell;
  g.pixels = static_cast<int>(c.size());
  std::vector<int64_t> keys;
  keys.reserve(c.size());
  for (const cv::Vec2d& p : c) keys.push_back(binKey(binOf(p[0], cell), binOf(p[1], cell)));
  std::sort(keys.begin(), keys.end());
  // bins with at least two pixels, each grown by one bin in x and y
  for (size_t i = 0; i + 1 < keys.size(); ++i) {
    if (keys[i] != keys[i + 1]) continue;
    const int64_t x = keys[i] / (int64_t{1} << 32) - (int64_t{1} << 30);
    const int64_t y = keys[i] % (int64_t{1} << 32) - (int64_t{1} << 30);
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy) g.bins.push_back(binKey(x + dx, y + dy));
    while (i + 1 < keys.size() && keys[i + 1] == keys[i]) ++i;
  }
  std::sort(g.bins.begin(), g.bins.end());
  g.bins.erase(std::unique(g.bins.begin(), g.bins.end()), g.bins.end());
  return g;
}

double chromaOutside(const ChromaGamut& gamut, const cv::Mat& image, const cv::Mat& mask,
                     float darkFloor) {
  std::vector<cv::Vec2d> c = logChromaticities(image, mask, darkFloor, "chromaOutside");
  if (c.empty() || gamut.bins.empty()) return 0.0;
  centreOnMedian(c);
  size_t outside = 0;
  for (const cv::Vec2d& p : c) outside += gamut.contains(p[0], p[1]) ? 0 : 1;
  return static_cast<double>(outside) / static_cast<double>(c.size());
}

}  // namespace ps

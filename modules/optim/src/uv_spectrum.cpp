#include "photoscene/optim/uv_spectrum.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "photoscene/core/error.hpp"
#include "photoscene/core/color.hpp"

namespace ps {
namespace {

// Centred log-magnitude spectrum of a real image, radially band-passed: the lowest radii hold the
// window's own spectrum, the corners lie past the log-polar circle.
cv::Mat logSpectrum(const cv::Mat& img) {
  cv::Mat planes[2] = {img.clone(), cv::Mat::zeros(img.size(), CV_32F)}, complex;
  cv::merge(planes, 2, complex);
  cv::dft(complex, complex);
  cv::split(complex, planes);
  cv::Mat mag;
  cv::magnitude(planes[0], planes[1], mag);
  const double mean = cv::mean(mag)[0];
  if (!(mean > 0)) return cv::Mat::zeros(img.size(), CV_32F);
  cv::log(1.0 + mag / mean, mag);
  // fftshift
  const int M = mag.rows, h = M / 2;
  cv::Mat s(mag.size(), CV_32F);
  mag(cv::Rect(h, h, M - h, M - h)).copyTo(s(cv::Rect(0, 0, M - h, M - h)));
  mag(cv::Rect(0, 0, h, h)).copyTo(s(cv::Rect(M - h, M - h, h, h)));
  mag(cv::Rect(h, 0, M - h, h)).copyTo(s(cv::Rect(0, M - h, M - h, h)));
  mag(cv::Rect(0, h, h, M - h)).copyTo(s(cv::Rect(M - h, 0, h, M - h)));
  for (int y = 0; y < M; ++y)
    for (int x = 0; x < M; ++x) {
      const double r = std::hypot(x - h, y - h);
      const double lowCut = 1.0 - std::exp(-r * r / (2.0 * 3.0 * 3.0));
      s.at<float>(y, x) *= static_cast<float>(r < h ? lowCut : 0.0);
    }
  return s;
}

// Log-polar image of a centred spectrum: rows = angle over [0, 2 pi), columns = log radius over
// [0, log(M / 2)); each column's mean over the angles removed (isotropic content carries no
// rotation and blurs the correlation).
cv::Mat logPolar(const cv::Mat& spec, int L) {
  const int M = spec.rows;
  cv::Mat lp;
  cv::warpPolar(spec, lp, cv::Size(L, L), cv::Point2f(M / 2.0f, M / 2.0f), M / 2.0,
                static_cast<int>(cv::INTER_LINEAR) | static_cast<int>(cv::WARP_POLAR_LOG));
  cv::Mat colMean, rowMean;
  cv::reduce(lp, colMean, 0, cv::REDUCE_AVG);
  for (int y = 0; y < lp.rows; ++y) lp.row(y) -= colMean;
  // and each row's mean over the radii: a line through the origin (the spectrum of the mask's
  // straight edges) is a row here, where a periodic pattern's peaks are spots
  cv::reduce(lp, rowMean, 1, cv::REDUCE_AVG);
  for (int x = 0; x < lp.cols; ++x) lp.col(x) -= rowMean;
  return lp;
}

}  // namespace

UvSpectrumEstimate estimateSimilarityBySpectrum(const cv::Mat& photo, const cv::Mat& weight,
                                                const cv::Mat& graph, double graphCellRatio,
                                                const UvSpectrumOptions& o) {
  PS_Check(
      photo.type() == CV_32FC1 && weight.type() == CV_32FC1 && graph.type() == CV_32FC1 &&
          photo.size() == weight.size() && photo.size() == graph.size() && photo.rows == photo.cols,
      "estimateSimilarityBySpectrum: photo, weight and graph must be square CV_32FC1 of one size");
  UvSpectrumEstimate e;
  const double wsum = cv::sum(weight)[0];
  if (!(wsum > 16) || photo.rows < 16) return e;
  auto windowed = [&](const cv::Mat& img, const cv::Mat& w) {
    const double mean = cv::sum(img.mul(w))[0] / cv::sum(w)[0];
    cv::Mat out = (img - mean).mul(w);
    return out;
  };
  // the graph raster holds whole periods: its DFT has no leakage and needs no window
  const cv::Mat ones(photo.size(), CV_32F, cv::Scalar(1));
  const int L = o.logPolarSize;
  const cv::Mat lpG = logPolar(logSpectrum(windowed(graph, ones)), L);
  const cv::Mat lpP = logPolar(logSpectrum(windowed(photo, weight)), L);
  // cross-correlation, circular in the angle, linear in the log radius (zero padding): a matched
  // filter, steadier here than phase correlation, which whitens the spectra's noise up to the
  // peaks' level
  cv::Mat a = cv::Mat::zeros(L, 2 * L, CV_32F), b = cv::Mat::zeros(L, 2 * L, CV_32F);
  lpG.copyTo(a(cv::Rect(0, 0, L, L)));
  lpP.copyTo(b(cv::Rect(0, 0, L, L)));
  cv::Mat fa, fb, cross, corr;
  cv::dft(a, fa, cv::DFT_COMPLEX_OUTPUT);
  cv::dft(b, fb, cv::DFT_COMPLEX_OUTPUT);
  cv::mulSpectrums(fb, fa, cross, 0, true);  // corr(d) = sum_x a(x) b(x + d)
  cv::idft(cross, corr, cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  cv::Point peak;
  double peakValue = 0;
  cv::minMaxLoc(corr, nullptr, &peakValue, nullptr, &peak);
  const double norm = std::sqrt(cv::norm(lpG, cv::NORM_L2SQR) * cv::norm(lpP, cv::NORM_L2SQR));
  const double response = norm > 0 ? peakValue / norm : 0.0;
  // sub-cell peak: a parabola through the neighbours, circular in both axes of corr
  auto at = [&](int y, int x) {
    return corr.at<float>((y + corr.rows) % corr.rows, (x + corr.cols) % corr.cols);
  };
  auto vertex = [](double l, double c, double r) {
    const double d = l - 2 * c + r;
    return d < 0 ? 0.5 * (l - r) / d : 0.0;
  };
  double sx = peak.x + vertex(at(peak.y, peak.x - 1), peakValue, at(peak.y, peak.x + 1));
  double sy = peak.y + vertex(at(peak.y - 1, peak.x), peakValue, at(peak.y + 1, peak.x));
  if (sx > L) sx -= 2 * L;  // negative radial shifts wrap to the end
  if (sy > L / 2.0) sy -= L;
  const cv::Point2d shift(sx, sy);
  // photo(u) = graph(s R u): a graph peak at frequency w appears at s R^T w, so the photo's log
  // radius is the graph's plus log s and its angle the graph's minus the rotation
  const double perColumn = std::log(photo.rows / 2.0) / L;
  // bin k is k / (M cell) cycles per uv unit on each raster
  e.logScale = static_cast<float>(shift.x * perColumn + std::log(graphCellRatio));
  double rot = -shift.y * 2 * kPi / L;
  rot = std::fmod(std::fmod(rot, kPi) + kPi, kPi);
  e.rotation = static_cast<float>(rot);
  e.response = response;
  e.ok = response >= o.minResponse;
  return e;
}

UvSpectrumEstimate estimateUvBySpectrum(const PartGeometry& geo, const cv::Mat& photo,
                                        const cv::Mat& shading, const cv::Mat& mapLuminance,
                                        const UvSpectrumOptions& o) {
  PS_Check(photo.type() == CV_32FC3 && photo.size() == geo.imageSize,
           "estimateUvBySpectrum: photo must be CV_32FC3 of the geometry's size");
  PS_Check(shading.empty() || (shading.type() == CV_32FC3 && shading.size() == geo.imageSize),
           "estimateUvBySpectrum: shading must be empty or CV_32FC3 of the geometry's size");
  PS_Check(mapLuminance.type() == CV_32FC1 && mapLuminance.rows == mapLuminance.cols &&
               mapLuminance.rows >= 4,
           "estimateUvBySpectrum: mapLuminance must be square CV_32FC1");
  UvSpectrumEstimate e;
  const int n = geo.size();
  if (n < 256) return e;
  // the uv cell: the median pixel footprint (finer would leave most cells empty)
  std::vector<float> fp;
  Vec2f lo(1e30f, 1e30f), hi(-1e30f, -1e30f);
  for (int i = 0; i < n; ++i) {
    const auto& d = geo.data[i];
    if (!(d.footprint > 0) || !std::isfinite(d.footprint) || !d.uv.allFinite()) continue;
    fp.push_back(d.footprint);
    lo = lo.cwiseMin(d.uv);
    hi = hi.cwiseMax(d.uv);
  }
  if (fp.size() < 256) return e;
  std::nth_element(fp.begin(), fp.begin() + fp.size() / 2, fp.end());
  double cell = fp[fp.size() / 2];
  const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  if (!(cell > 0) || !(extent > 0)) return e;
  int M = static_cast<int>(std::ceil(extent / cell)) + 1;
  if (M > o.maxRaster) {
    M = o.maxRaster;
    cell = extent / (M - 1);
  }
  M = cv::getOptimalDFTSize(std::max(M, 16));
  if (M % 2) ++M;
  // splat luminance (over the white material's, where given) into the raster
  cv::Mat sum = cv::Mat::zeros(M, M, CV_32F), count = cv::Mat::zeros(M, M, CV_32F);
  auto lum = [](const cv::Vec3f& c) { return luminance(c); };
  for (int i = 0; i < n; ++i) {
    const auto& d = geo.data[i];
    if (!(d.footprint > 0) || !std::isfinite(d.footprint) || !d.uv.allFinite()) continue;
    float v = lum(photo.at<cv::Vec3f>(geo.pixels[i]));
    if (!shading.empty()) {
      const float s = lum(shading.at<cv::Vec3f>(geo.pixels[i]));
      if (!(s > 1e-6f)) continue;
      v /= s;
    }
    if (!std::isfinite(v)) continue;
    const int x = static_cast<int>(std::lround((d.uv.x() - lo.x()) / cell));
    const int y = static_cast<int>(std::lround((d.uv.y() - lo.y()) / cell));
    if (x < 0 || y < 0 || x >= M || y >= M) continue;
    sum.at<float>(y, x) += v;
    count.at<float>(y, x) += 1;
  }
  // normalized convolution fills the cells between samples; cells far from any sample get weight 0
  cv::Mat sb, cb;
  cv::GaussianBlur(sum, sb, cv::Size(0, 0), 1.0);
  cv::GaussianBlur(count, cb, cv::Size(0, 0), 1.0);
  cv::Mat raster(M, M, CV_32F), valid(M, M, CV_32F);
  for (int y = 0; y < M; ++y)
    for (int x = 0; x < M; ++x) {
      const float c = cb.at<float>(y, x);
      const bool ok = c > 0.15f;
      raster.at<float>(y, x) = ok ? sb.at<float>(y, x) / c : 0.0f;
      valid.at<float>(y, x) = ok ? 1.0f : 0.0f;
    }
  // a soft edge: the window's own spectrum stays narrow
  cv::Mat weight, inner;
  cv::erode(valid, inner, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(7, 7)));
  cv::GaussianBlur(inner, weight, cv::Size(0, 0), 3.0);
  weight = weight.mul(valid);
  // the graph at logScale 0, rotation 0 on a raster of the same size holding whole periods, at
  // least 128 cells a period (its finest structure resolved; the photo raster's cells are the
  // camera's pixels and may be far coarser)
  const int periods = std::max(1, M / 128);
  const double cellG = static_cast<double>(periods) / M;
  const int Nm = mapLuminance.rows;
  const cv::Mat& map = mapLuminance;
  cv::Mat graph(M, M, CV_32F);
  for (int y = 0; y < M; ++y)
    for (int x = 0; x < M; ++x) {
      // texel centres at (i + 0.5) / N, wrapped; raster y follows v, map rows run against it
      double fx = x * cellG * Nm - 0.5, fy = (1.0 - y * cellG) * Nm - 0.5;
      fx -= std::floor(fx / Nm) * Nm;
      fy -= std::floor(fy / Nm) * Nm;
      const int x0 = std::min(static_cast<int>(fx), Nm - 1),
                y0 = std::min(static_cast<int>(fy), Nm - 1);
      const float ax = static_cast<float>(fx - x0), ay = static_cast<float>(fy - y0);
      const int x1 = (x0 + 1) % Nm, y1 = (y0 + 1) % Nm;
      const float a = map.at<float>(y0, x0), b = map.at<float>(y0, x1), c = map.at<float>(y1, x0),
                  d = map.at<float>(y1, x1);
      graph.at<float>(y, x) = (1 - ay) * ((1 - ax) * a + ax * b) + ay * ((1 - ax) * c + ax * d);
    }
  return estimateSimilarityBySpectrum(raster, weight, graph, cellG / cell, o);
}

}  // namespace ps

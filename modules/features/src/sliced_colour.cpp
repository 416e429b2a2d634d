#include "sliced_colour.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ps::features_detail {

const std::vector<cv::Vec3d>& slicedDirections() {
  static const std::vector<cv::Vec3d> dirs = [] {
    std::vector<cv::Vec3d> d = {
        {0.2126, 0.7152, 0.0722},  // luminance
        {1, 0, 0},   {0, 1, 0},   {0, 0, 1},  // the channels
        {1, -1, 0},  {1, 1, -2},  {1, 0, -1},  // opponent axes: red-green, yellow-blue, red-blue
    };
    for (auto& v : d) v /= cv::norm(v);
    return d;
  }();
  return dirs;
}

namespace {

float project(const cv::Vec3f& c, const cv::Vec3d& d) {
  return float(c[0] * d[0] + c[1] * d[1] + c[2] * d[2]);
}

}  // namespace

SlicedTarget makeSlicedTarget(const cv::Mat& crop, const cv::Mat& mask0, double nu,
                              const cv::Vec3d& noise) {
  SlicedTarget t;
  t.nu = nu;
  for (int y = 0; y < mask0.rows; ++y)
    for (int x = 0; x < mask0.cols; ++x)
      if (mask0.at<float>(y, x) > 0.5f) t.pixels.emplace_back(x, y);
  const auto& dirs = slicedDirections();
  t.sorted.resize(dirs.size());
  const size_t n = t.pixels.size();
  for (size_t k = 0; k < dirs.size(); ++k) {
    std::vector<float>& v = t.sorted[k];
    v.resize(n);
    for (size_t i = 0; i < n; ++i)
      v[i] = float(project(crop.at<cv::Vec3f>(t.pixels[i]), dirs[k]) / nu);
    std::sort(v.begin(), v.end());
    const double s2 = (noise[0] * noise[0] * dirs[k][0] * dirs[k][0] +
                       noise[1] * noise[1] * dirs[k][1] * dirs[k][1] +
                       noise[2] * noise[2] * dirs[k][2] * dirs[k][2]) /
                      (nu * nu);
    if (s2 <= 0 || n < 2) continue;
    const double mean = std::accumulate(v.begin(), v.end(), 0.0) / double(n);
    double var = 0;
    for (float e : v) var += (e - mean) * (e - mean);
    var /= double(n);
    if (var <= 0) continue;
    const double shrink = std::sqrt(std::max(0.0, var - s2) / var);
    for (float& e : v) e = float(mean + shrink * (e - mean));
  }
  return t;
}

double slicedForward(const cv::Mat& crop, const SlicedTarget& target, SlicedState& state) {
  const auto& dirs = slicedDirections();
  const size_t n = target.pixels.size();
  state.residual.assign(dirs.size(), std::vector<float>(n, 0.f));
  if (n == 0) return 0.0;
  std::vector<float> proj(n);
  std::vector<int> order(n);
  double loss = 0;
  for (size_t k = 0; k < dirs.size(); ++k) {
    for (size_t i = 0; i < n; ++i)
      proj[i] = float(project(crop.at<cv::Vec3f>(target.pixels[i]), dirs[k]) / target.nu);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return proj[a] < proj[b]; });
    double sum = 0;
    for (size_t r = 0; r < n; ++r) {
      const int i = order[r];
      const float e = proj[i] - target.sorted[k][r];
      state.residual[k][i] = e;
      sum += double(e) * e;
    }
    loss += sum / double(n);
  }
  return loss / double(dirs.size());
}

void slicedBackward(const SlicedTarget& target, const SlicedState& state, double scale,
                    cv::Mat& gradCrop) {
  const auto& dirs = slicedDirections();
  const size_t n = target.pixels.size();
  if (n == 0) return;
  // d/d proj_i of (1 / K) sum_k (1 / n) sum e^2 = 2 e / (K n); proj = d . c / nu
  const double c = scale * 2.0 / (double(dirs.size()) * double(n) * target.nu);
  for (size_t i = 0; i < n; ++i) {
    cv::Vec3d g(0, 0, 0);
    for (size_t k = 0; k < dirs.size(); ++k) g += dirs[k] * double(state.residual[k][i]);
    cv::Vec3f& out = gradCrop.at<cv::Vec3f>(target.pixels[i]);
    for (int ch = 0; ch < 3; ++ch) out[ch] += float(c * g[ch]);
  }
}

}  // namespace ps::features_detail

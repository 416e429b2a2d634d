// Discrete and piecewise-constant distributions for light and environment sampling.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "photoscene/core/math.hpp"

namespace ps {

/// A discrete distribution over n items with non-negative weights.
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(const std::vector<float>& w) {
    cdf_.assign(w.size() + 1, 0.0);
    for (size_t i = 0; i < w.size(); ++i) {
      const double x = std::isfinite(w[i]) && w[i] > 0 ? w[i] : 0.0;
      cdf_[i + 1] = cdf_[i] + x;
    }
    total_ = cdf_.back();
  }
  bool empty() const { return !(total_ > 0); }
  size_t size() const { return cdf_.empty() ? 0 : cdf_.size() - 1; }
  float total() const { return static_cast<float>(total_); }
  float pdf(int i) const {
    if (empty() || i < 0 || i >= static_cast<int>(size())) return 0.0f;
    return static_cast<float>((cdf_[i + 1] - cdf_[i]) / total_);
  }
  /// Index drawn with probability w_i / total; `pdf` receives that probability. `uRemapped`
  /// (optional) receives u rescaled to [0, 1) within the chosen item.
  int sample(float u, float* pdf, float* uRemapped = nullptr) const {
    const double x = static_cast<double>(u) * total_;
    int i = static_cast<int>(std::upper_bound(cdf_.begin(), cdf_.end(), x) - cdf_.begin()) - 1;
    i = std::clamp(i, 0, static_cast<int>(size()) - 1);
    while (i > 0 && cdf_[i + 1] - cdf_[i] <= 0) --i;  // never return a zero-weight item
    while (i + 1 < static_cast<int>(size()) && cdf_[i + 1] - cdf_[i] <= 0) ++i;
    const double d = cdf_[i + 1] - cdf_[i];
    *pdf = static_cast<float>(d / total_);
    if (uRemapped) *uRemapped = d > 0 ? static_cast<float>(std::clamp((x - cdf_[i]) / d, 0.0, 0.99999994)) : 0.5f;
    return i;
  }

 private:
  std::vector<double> cdf_;
  double total_ = 0;
};

/// Piecewise-constant density over [0, 1)^2 on a W x H grid (row 0 at v = 0).
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<float>& w, int width, int height) : width_(width), height_(height) {
    std::vector<float> rowSums(height, 0.0f);
    rows_.reserve(height);
    for (int y = 0; y < height; ++y) {
      std::vector<float> r(w.begin() + static_cast<size_t>(y) * width, w.begin() + static_cast<size_t>(y + 1) * width);
      rows_.emplace_back(r);
      rowSums[y] = rows_.back().total();
    }
    marginal_ = Distribution1D(rowSums);
  }
  bool empty() const { return marginal_.empty(); }
  /// Density in (u, v) (integrates to 1 over the unit square).
  float pdf(const Vec2f& uv) const {
    if (empty()) return 0.0f;
    const int x = std::clamp(static_cast<int>(uv.x() * width_), 0, width_ - 1);
    const int y = std::clamp(static_cast<int>(uv.y() * height_), 0, height_ - 1);
    return marginal_.pdf(y) * rows_[y].pdf(x) * width_ * height_;
  }
  Vec2f sample(float u1, float u2, float* pdf) const {
    float py = 0, px = 0, ry = 0, rx = 0;
    const int y = marginal_.sample(u1, &py, &ry);
    const int x = rows_[y].sample(u2, &px, &rx);
    *pdf = py * px * width_ * height_;
    return Vec2f((x + rx) / width_, (y + ry) / height_);
  }

 private:
  int width_ = 0, height_ = 0;
  std::vector<Distribution1D> rows_;
  Distribution1D marginal_;
};

}  // namespace ps

#include "photoscene/optim/adam.hpp"

#include <cmath>
#include <limits>
#include <numeric>

#include "photoscene/core/error.hpp"

namespace ps {

bool AdamOptions::IsValid(std::string* error) const {
  if (!(learningRate > 0) || !(beta1 >= 0 && beta1 < 1) || !(beta2 >= 0 && beta2 < 1) || !(epsilon > 0)) {
    if (error) *error = "learningRate > 0, beta1 and beta2 in [0, 1), epsilon > 0";
    return false;
  }
  return true;
}

Adam::Adam(size_t size, const AdamOptions& options)
    : options_(options), m_(size, 0.f), v_(size, 0.f), scales_(size, 1.f), mask_(size, 1) {
  std::string why;
  PS_Check(options.IsValid(&why), why);
}

void Adam::setMask(const std::vector<uint8_t>& mask) {
  PS_CheckEQ(mask.size(), m_.size(), "Adam mask size");
  mask_ = mask;
}

void Adam::setBounds(const std::vector<float>& lower, const std::vector<float>& upper) {
  PS_CheckEQ(lower.size(), m_.size(), "Adam lower bound size");
  PS_CheckEQ(upper.size(), m_.size(), "Adam upper bound size");
  lower_ = lower;
  upper_ = upper;
}

void Adam::setScales(const std::vector<float>& scales) {
  PS_CheckEQ(scales.size(), m_.size(), "Adam scales size");
  scales_ = scales;
}

void Adam::step(std::vector<float>& values, const std::vector<float>& gradient) {
  PS_CheckEQ(values.size(), m_.size(), "Adam values size");
  PS_CheckEQ(gradient.size(), m_.size(), "Adam gradient size");
  ++t_;
  const double c1 = 1.0 - std::pow(static_cast<double>(options_.beta1), t_);
  const double c2 = 1.0 - std::pow(static_cast<double>(options_.beta2), t_);
  for (size_t i = 0; i < values.size(); ++i) {
    if (!mask_[i] || !std::isfinite(gradient[i])) continue;
    const float g = gradient[i];
    m_[i] = options_.beta1 * m_[i] + (1 - options_.beta1) * g;
    v_[i] = options_.beta2 * v_[i] + (1 - options_.beta2) * g * g;
    const double mhat = m_[i] / c1, vhat = v_[i] / c2;
    values[i] -= static_cast<float>(options_.learningRate * scales_[i] * mhat / (std::sqrt(vhat) + options_.epsilon));
    if (!lower_.empty()) values[i] = std::max(lower_[i], std::min(upper_[i], values[i]));
  }
}

void Adam::reset() {
  std::fill(m_.begin(), m_.end(), 0.f);
  std::fill(v_.begin(), v_.end(), 0.f);
  t_ = 0;
}

bool PlateauOptions::IsValid(std::string* error) const {
  if (window < 1 || !(minRelativeImprovement >= 0) || minIterations < 0) {
    if (error) *error = "window >= 1, minRelativeImprovement >= 0, minIterations >= 0";
    return false;
  }
  return true;
}

PlateauDetector::PlateauDetector(const PlateauOptions& options)
    : options_(options), best_(std::numeric_limits<double>::infinity()) {
  std::string why;
  PS_Check(options.IsValid(&why), why);
}

void PlateauDetector::reset() {
  history_.clear();
  iterations_ = 0;
  best_ = std::numeric_limits<double>::infinity();
}

bool PlateauDetector::update(double loss) {
  ++iterations_;
  if (!std::isfinite(loss)) return true;
  best_ = std::min(best_, loss);
  history_.push_back(loss);
  const size_t w = static_cast<size_t>(options_.window);
  while (history_.size() > 2 * w) history_.pop_front();
  if (iterations_ < options_.minIterations || history_.size() < 2 * w) return false;
  const double older = std::accumulate(history_.begin(), history_.begin() + w, 0.0) / w;
  const double recent = std::accumulate(history_.begin() + w, history_.end(), 0.0) / w;
  const double improvement = (older - recent) / std::max(std::abs(older), 1e-30);
  return improvement < options_.minRelativeImprovement;
}

}  // namespace ps

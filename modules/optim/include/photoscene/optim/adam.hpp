// First-order optimisation over a flat parameter vector (the layout of MaterialGraph::values()
// and friends): Adam with per-entry masks and box constraints, and a moving-average plateau
// detector for early stopping.
//
//   ps::Adam adam(values.size(), {.learningRate = 0.02f});
//   adam.setBounds(lower, upper);              // projection after every step
//   adam.setMask(graph.differentiableMask());  // discrete entries never move
//   ps::PlateauDetector plateau({.window = 20, .minRelativeImprovement = 1e-3});
//   for (int it = 0; it < maxIterations && !plateau.update(loss); ++it) {
//     ... loss, grad = evaluate(values) ...
//     adam.step(values, grad);
//   }
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace ps {

struct AdamOptions {
  float learningRate = 0.01f;
  float beta1 = 0.9f;
  float beta2 = 0.999f;
  float epsilon = 1e-8f;
  bool IsValid(std::string* error) const;
};

/// Adam (Kingma and Ba 2015) with bias correction. Non-finite gradient entries are treated as 0
/// (the step is skipped for them), so one bad pixel cannot poison the parameters.
class Adam {
 public:
  Adam(size_t size, const AdamOptions& options = {});
  /// Entries with mask 0 are never changed (discrete parameters).
  void setMask(const std::vector<uint8_t>& mask);
  /// Box constraints applied after each step.
  void setBounds(const std::vector<float>& lower, const std::vector<float>& upper);
  /// Per-entry learning-rate multipliers (e.g. larger steps for UV offsets).
  void setScales(const std::vector<float>& scales);
  void setLearningRate(float lr) { options_.learningRate = lr; }
  float learningRate() const { return options_.learningRate; }
  /// One step: values -= lr * mhat / (sqrt(vhat) + eps), then projected.
  void step(std::vector<float>& values, const std::vector<float>& gradient);
  /// Forgets the moment estimates (after a discrete jump such as a UV search).
  void reset();
  int steps() const { return t_; }

 private:
  AdamOptions options_;
  std::vector<float> m_, v_, lower_, upper_, scales_;
  std::vector<uint8_t> mask_;
  int t_ = 0;
};

struct PlateauOptions {
  int window = 20;                      ///< iterations in each moving average
  double minRelativeImprovement = 1e-3; ///< stop when the average improves less than this
  int minIterations = 0;                ///< never stop before this many updates
  bool IsValid(std::string* error) const;
};

/// Early stopping: compares the mean loss of the last `window` iterations with the mean of the
/// `window` before; update() returns true once the relative improvement falls below the
/// threshold (or the loss stops being finite).
class PlateauDetector {
 public:
  explicit PlateauDetector(const PlateauOptions& options = {});
  bool update(double loss);
  int iterations() const { return iterations_; }
  double best() const { return best_; }
  void reset();

 private:
  PlateauOptions options_;
  std::deque<double> history_;
  int iterations_ = 0;
  double best_;
};

}  // namespace ps

// Gradient checking as a first-class tool (Ceres style): compares the analytic backward pass with
// central finite differences of a scalar test loss L = sum(w * map) (w: fixed smooth random weights
// per map), for every continuous parameter.
//
// Tolerance: a parameter passes when |analytic - fd| <= absTol + relTol * max(|analytic|, |fd|)
// for at least one of the steps h in `steps` (relative to the parameter's range). Several steps
// make the check robust to the few kinks (clamps, cell boundaries) that a step may cross.
// Graph checks use one-sided differences (into the range) for a value at the end of its range.
#pragma once

#include "photoscene/graph/material_graph.hpp"

#include <string>
#include <vector>

namespace ps {

struct GradientCheckOptions {
  int size = 32;                 ///< map size for the check (power of two)
  bool doublePrecision = true;   ///< run the forward and backward kernels in double
  std::vector<double> steps = {1e-3, 3e-4, 1e-4, 1e-5, 1e-6};  ///< FD steps, fractions of the range
  double relTol = 2e-2;
  double absTol = 1e-3;          ///< in units of the loss per unit of the normalized parameter
  uint64_t seed = 1;             ///< weights (and inputs for node checks)
  bool IsValid(std::string* error) const;
};

struct GradientCheckEntry {
  std::string parameter;  ///< "name" or "name[k]" for a color component; "input:<port>" for inputs
  double analytic = 0, finiteDifference = 0, step = 0;
  bool ok = false;
};

struct GradientCheckReport {
  std::vector<GradientCheckEntry> entries;
  bool ok() const {
    for (const auto& e : entries)
      if (!e.ok) return false;
    return true;
  }
  std::string summary() const;  ///< one line per failing entry
};

/// Checks every continuous parameter of `graph` at its current values.
GradientCheckReport checkGraphGradients(const MaterialGraph& graph,
                                        const GradientCheckOptions& options = {});

/// Checks one node type alone: random smooth inputs, parameters at `paramValues` (the node's flat
/// parameter vector; empty = defaults), every continuous parameter plus directional derivatives
/// along random smooth perturbations of every image input.
GradientCheckReport checkNodeGradients(const std::string& nodeType,
                                       const std::vector<float>& paramValues = {},
                                       const GradientCheckOptions& options = {});

}  // namespace ps

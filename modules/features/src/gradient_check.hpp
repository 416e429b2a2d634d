// The summary every finite-difference check of the features module shares: analytic against
// central differences at steps h (`numeric`) and 2h (`numeric2`), whose disagreement measures the
// float round-off of the loss and so sets the floor below which an error is not resolvable.
#pragma once

#include <vector>

#include "photoscene/features/texture_loss.hpp"

namespace ps {

/// `analytic`, `numeric` and `numeric2` have one entry per checked derivative, in the same order.
TextureLossGradientCheck summarizeGradientCheck(const std::vector<double>& analytic,
                                                const std::vector<double>& numeric,
                                                const std::vector<double>& numeric2);

}  // namespace ps

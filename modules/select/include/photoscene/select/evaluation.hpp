// Measuring graph selection: held-out random draws of every library graph, rendered under a
// random UV rotation and scale and a random lighting color and level, selected through a bank.
// Two protocols: "canonical" (issue 5: a flat frontal patch, as the bank's canonical exemplars)
// and "observed" (a plane in perspective with UVs, shading gradient, blur, noise and an odd
// mask, queried through selectForPart as the pipeline queries a photographed part).
#pragma once

#include <map>
#include <string>

#include "photoscene/select/exemplar_bank.hpp"

namespace ps {

struct HeldOutOptions {
  int drawsPerGraph = 5;
  float minUvScale = 1.5f, maxUvScale = 5.0f;  ///< log-uniform texture repeats
  float minLevel = 0.3f, maxLevel = 3.0f;      ///< log-uniform light level
  float colorJitter = 0.4f;                    ///< per-channel light color in [1 - j, 1 + j]
  float spread = 0.6f;                         ///< randomValues spread of the held-out draws
  int k = 21;
  bool categoryFirst = false;  ///< ExemplarBank::select's category-first vote
  bool distinctDraws = false;  ///< ExemplarBank::select: k nearest draws vote
  /// false: canonical patches (issue 5's protocol); true: observed planes (ObservationRanges of
  /// the bank's options, other seeds), queried with their UVs through selectForPart.
  bool observed = false;
  uint64_t seed = 2024;  ///< differs from the bank's draws
};

struct SelectionReport {
  int total = 0, top1 = 0, category = 0;
  double top1Accuracy() const { return total ? double(top1) / total : 0; }
  double categoryAccuracy() const { return total ? double(category) / total : 0; }
  std::map<std::string, std::map<std::string, int>>
      categoryConfusion;  ///< truth -> chosen -> count
  std::map<std::string, int> correctPerGraph;
  double querySeconds = 0;  ///< total time of key extraction + kNN over all queries
  /// A printable table: accuracies, the category confusion, graphs below half right.
  std::string table() const;
};

/// Renders held-out draws with renderCanonicalPatch at the bank's renderSize and selects them.
SelectionReport evaluateSelection(const ExemplarBank& bank, const GraphLibrary& library,
                                  const ExemplarBankOptions& bankOptions,
                                  const HeldOutOptions& options = {});

}  // namespace ps

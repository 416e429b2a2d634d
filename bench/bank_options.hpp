// Command-line options (CLI11) shared by the selection benchmarks: the exemplar bank's build
// options that both ps_bench_select and ps_bench_select_sample vary.
#pragma once

#include <CLI/CLI.hpp>

#include "photoscene/select.hpp"

namespace ps::bench {

/// --draws, --observed, --shading, --stats and --scales (comma-separated) into `options`.
inline void addBankOptions(CLI::App& app, ExemplarBankOptions& options) {
  app.add_option("--draws", options.drawsPerGraph, "random draws per graph");
  app.add_option("--observed", options.observedPerDraw, "observed-plane exemplars per draw");
  app.add_option("--shading", options.shadingSigma,
                 "smooth shading removal, sigma in pixels (0: off)");
  app.add_option("--stats", options.statisticsWeight,
                 "weight of the intensity and chroma statistics");
  app.add_option("--scales", options.uvScales, "canonical UV scales, comma-separated")
      ->delimiter(',');
}

}  // namespace ps::bench

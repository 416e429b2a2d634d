// The method as a list of stages (stages.hpp; each stage's file says what it reads and writes).
// The runner orders them by what they declare, derives their cache keys, and times them.
#include "photoscene/pipeline/pipeline.hpp"

#include <fmt/format.h>

#include "photoscene/core.hpp"
#include "photoscene/core/memory.hpp"
#include "runner.hpp"
#include "stages.hpp"

namespace ps {

namespace pipeline {

StageList pipelineStages(const PipelineOptions& options) {
  StageList s;
  s.push_back(makePartsStage());      // what each part gets (scene.json)
  s.push_back(makePosesStage());      // furniture moved onto the labels (before any render)
  s.push_back(makeGeometryStage());   // per view: G-buffers
  s.push_back(makeAlignStage());      // per view: M_photo, Eq. (1), M_aln
  s.push_back(makeObserveStage());    // per part: its view and median colour
  s.push_back(makePinStage());        // the scale of the neutral albedos
  s.push_back(makeLightsStage(0));    // emitters under the neutral materials
  s.push_back(makeIncidentStage(0));  // per view: incident-light grids
  if (options.baseline == Baseline::None) {
    s.push_back(makeSelectStage());     // per part: the graph
    s.push_back(makeFitStage());        // per part: the fit
    s.push_back(makeRefineStage(0));    // per part: albedo scale under the first lights
    s.push_back(makeLightsStage(1));    // the global solve with the fitted materials
    s.push_back(makeIncidentStage(1));  // per view: new grids
    s.push_back(makeRefineStage(1));    // per part: the second round
    s.push_back(makeBounceStage());     // the albedos consistent with the light they bounce
    s.push_back(makeExportStage({"parts", "observe", "select", "fit", "refine1", "bounce", "lights1"}));
  } else {
    s.push_back(makeBaselineStage(options.baseline));  // under lights0
    s.push_back(makeExportStage({"parts", "observe", "pin", "lights0",
                                 std::string("baseline-") + baselineName(options.baseline)}));
  }
  s.push_back(makeMetricsStage());
  if (options.writeReport) s.push_back(makeReportStage());
  return s;
}

}  // namespace pipeline

PipelineResult runPipeline(const PipelineOptions& options) {
  using namespace pipeline;
  InterruptGuard interrupts;
  ThreadLimit threads(options.threads);
  std::unique_ptr<Context> ctx = Context::load(options);  // bad input: nothing written yet
  Runner runner(pipelineStages(options));
  fs::create_directories(options.out);
  ctx->cache =
      std::make_unique<StageCache>(options.useStageCache ? options.out / ".cache" : fs::path());
  spdlog::info("run: {}", ctx->describe());
  runner.run(*ctx);
  ctx->finishResult();
  spdlog::info("run: {:.1f} s, peak memory {:.0f} MiB", ctx->result.totalSeconds,
               ctx->result.peakMemoryMiB);
  return std::move(ctx->result);
}

}  // namespace ps

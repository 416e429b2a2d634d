// Every stage of the pipeline, one factory each (private to the module). pipeline.cpp lists them
// in order; each stage's file says what it declares and wires the module that does the work.
#pragma once

#include <memory>

#include "stage.hpp"

namespace ps::pipeline {

std::unique_ptr<Stage> makePartsStage();     ///< stage_parts.cpp: what each part gets
std::unique_ptr<Stage> makePosesStage();     ///< stage_poses.cpp: furniture moved onto the labels
std::unique_ptr<Stage> makeGeometryStage();  ///< stage_geometry.cpp: G-buffers per view
std::unique_ptr<Stage> makeAlignStage();     ///< stage_align.cpp: aligned masks per view
std::unique_ptr<Stage> makeObserveStage();   ///< stage_align.cpp: each part's view and median
std::unique_ptr<Stage> makePinStage();       ///< stage_align.cpp: the neutral albedos' scale
/// stage_lights.cpp: round 0 under the neutral materials, round 1 under the fitted ones
std::unique_ptr<Stage> makeLightsStage(int round);
std::unique_ptr<Stage> makeIncidentStage(int round);  ///< stage_incident.cpp: light grids per view
std::unique_ptr<Stage> makeSelectStage();             ///< stage_select.cpp: a graph per part
std::unique_ptr<Stage> makeFitStage();                ///< stage_fit.cpp: the per-part fit
std::unique_ptr<Stage> makeRefineStage(int round);    ///< stage_refine.cpp: albedo scale, roughness
/// stage_bounce.cpp: the albedos made consistent with the light they bounce
std::unique_ptr<Stage> makeBounceStage();
std::unique_ptr<Stage> makeBaselineStage(Baseline baseline);  ///< stage_baseline.cpp
/// stage_export.cpp: the output folder; reads the results of `after` (the last stages of the run)
std::unique_ptr<Stage> makeExportStage(std::vector<std::string> after);
std::unique_ptr<Stage> makeMetricsStage();  ///< stage_report.cpp: metrics.json
std::unique_ptr<Stage> makeReportStage();   ///< stage_report.cpp: report.html

/// The method's stages in order (pipeline.cpp); the baselines replace select..refine1.
StageList pipelineStages(const PipelineOptions& options);

}  // namespace ps::pipeline

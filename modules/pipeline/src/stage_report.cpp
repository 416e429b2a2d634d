// Stages `metrics` and `report`: metrics.json (eval's evaluateTwin against the photos and every
// ground truth the case folder holds, with the time and peak memory of every stage so far), then
// report.html (report module) from what the output folder holds.
#include <cmath>

#include "photoscene/core/log.hpp"

#include "photoscene/core/memory.hpp"
#include "photoscene/eval.hpp"
#include "photoscene/io.hpp"
#include "photoscene/report.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

class MetricsStage : public Stage {
 public:
  MetricsStage() : Stage("metrics") {
    decl.scene = {""};
    decl.options = {"preset", "eval_spp", "denoise", "ground_truth"};
    decl.after = {"export"};
    decl.writes = {"OUT/metrics.json"};
  }

  bool compute(Context& ctx, const Reads& in, int) override {
    const fs::path& out = in.out();
    eval::EvalOptions o;
    o.spp = in.evalSpp();
    o.denoise = in.denoise();
    o.seed = in.seed();
    const eval::TwinEvaluation e = eval::evaluateTwin(out, in.evalScene(), o);
    for (const std::string& n : e.notes) spdlog::info("metrics: {}", n);
    if (e.novel.empty() && e.relit.empty())
      spdlog::info("metrics: no novel or relit ground truth next to the scene: nothing rendered "
                   "for them");
    std::map<std::string, double> seconds;
    for (const StageRecord& r : ctx.result.stages) seconds[r.name] = r.seconds;
    seconds["metrics"] = e.seconds;
    eval::writeMetricsJson(out, e, seconds, in.preset(), ctx.clock.seconds());
    // peak resident memory (getrusage ru_maxrss, monotonic) at the end of each stage so far
    nlohmann::json metrics = io::readJsonFile(out / "metrics.json");
    nlohmann::json stages = nlohmann::json::object();
    for (const StageRecord& r : ctx.result.stages)
      stages[r.name] = std::round(r.peakMemoryMiB * 10) / 10;
    const double peak = peakMemoryMiB();
    stages["metrics"] = std::round(peak * 10) / 10;
    metrics["peak_memory_mib"] = {
        {"run", stages["metrics"]}, {"after_stage", stages}, {"source", "getrusage ru_maxrss"}};
    io::writeJsonFile(out / "metrics.json", metrics);
    return true;
  }
  void save(const Context&, int, Archive&) const override {}
  bool load(Context&, const Reads& in, int, Archive&) override {
    return fs::exists(in.out() / "metrics.json");
  }
};

class ReportStage : public Stage {
 public:
  ReportStage() : Stage("report") {
    decl.outputs = {"metrics.json"};  // `photoscene eval` may have written it again
    decl.after = {"export", "metrics"};
    decl.writes = {"OUT/report.html", "OUT/viewer/*", "OUT/renders/view<i>_diff.png"};
  }

  bool compute(Context&, const Reads& in, int) override {
    in.outFile("metrics.json");
    const ReportSummary r = writeReport(in.out());
    if (!r.viewerWritten) spdlog::warn("report.html has no 3D viewer: {}", r.viewerNote);
    return true;
  }
  void save(const Context&, int, Archive&) const override {}
  bool load(Context&, const Reads& in, int, Archive&) override {
    return fs::exists(in.out() / "report.html");
  }
};

}  // namespace

std::unique_ptr<Stage> makeMetricsStage() {
  return std::make_unique<MetricsStage>();
}
std::unique_ptr<Stage> makeReportStage() {
  return std::make_unique<ReportStage>();
}

}  // namespace ps::pipeline

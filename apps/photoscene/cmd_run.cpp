// `photoscene run SCENE.json -o OUT` and the no-argument demo.

#include <filesystem>

#include "commands.hpp"
#include "photoscene/core.hpp"
#include "photoscene/pipeline.hpp"
#include "photoscene/scene.hpp"

#include <cstdio>

namespace ps::app {

namespace fs = std::filesystem;

namespace {

struct RunArgs {
  std::string scene, out, preset, baseline, fitViews = "best";
  int textureSize = 1024;
  int threads = 0;
  int renderSpp = 0;  // 0: the preset's
  int evalSpp = 0;
  bool noDenoise = false;
};

void runPipeline(const RunArgs& args) {
  PipelineOptions o;
  o.scene = args.scene;
  o.out = args.out;
  if (!args.preset.empty()) o.preset = args.preset;
  o.textureSize = args.textureSize;
  o.threads = args.threads;
  o.baseline = parseBaseline(args.baseline);
  o.fitAllViews = args.fitViews == "all";
  if (args.renderSpp > 0) o.renderSpp = args.renderSpp;
  if (args.evalSpp > 0) o.evalSpp = args.evalSpp;
  o.denoise = !args.noDenoise;
  const PipelineResult r = ps::runPipeline(o);
  std::printf("%-12s %9s %9s %7s %9s\n", "stage", "seconds", "computed", "cached", "peak MiB");
  for (const StageRecord& s : r.stages)
    std::printf("%-12s %9.2f %9d %7d %9.0f\n", s.name.c_str(), s.seconds, s.computed, s.cached,
                s.peakMemoryMiB);
  std::printf("%-12s %9.2f %9s %7s %9.0f\n", "total", r.totalSeconds, "", "", r.peakMemoryMiB);
  for (size_t k = 0; k < r.lightNames.size(); ++k)
    std::printf("light %-14s radiance (%.3f, %.3f, %.3f)\n", r.lightNames[k].c_str(), r.lightRadiance[k].x(),
                r.lightRadiance[k].y(), r.lightRadiance[k].z());
  std::printf("wrote %s\n", r.out.string().c_str());
}

}  // namespace

void addRunCommand(CLI::App& root) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = root.add_subcommand("run", "Build the digital twin of a scene into an output folder");
  cmd->add_option("scene", args->scene, "scene.json")->required();
  cmd->add_option("-o,--out", args->out, "Output folder")->required();
  cmd->add_option("--preset", args->preset, "fast | balanced | paper (default: scene.json's, else balanced)")
      ->check(CLI::IsMember({"fast", "balanced", "paper"}));
  cmd->add_option("--texture-size", args->textureSize, "Size of the exported texture maps (pixels)")
      ->check(CLI::Range(4, 16384));
  cmd->add_option("--baseline", args->baseline, "pixel-median | shading-median: a baseline of the paper instead of the method")
      ->check(CLI::IsMember({"none", "pixel-median", "shading-median"}));
  cmd->add_option("--fit-views", args->fitViews,
                  "best (default): a part is fitted in the view that sees it best | all: a "
                  "homogeneous part over every view that sees it well, pooled")
      ->check(CLI::IsMember({"best", "all"}));
  cmd->add_option("--render-spp", args->renderSpp,
                  "Samples per pixel of the final renders of the input views (default: the "
                  "preset's: fast 8, balanced 16, paper 64)")
      ->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--eval-spp", args->evalSpp,
                  "Samples per pixel of the evaluation's novel and relit renders (default: the "
                  "preset's: fast 8, balanced 8, paper 32)")
      ->check(CLI::Range(1, 1 << 16));
  cmd->add_flag("--no-denoise", args->noDenoise,
                "Keep the final and evaluation renders as path traced (default: denoised)");
  cmd->add_option("--threads", args->threads, "Worker threads (default: all cores)")->check(CLI::Range(0, 1024));
  cmd->footer(
      "Exit status: 0 done; 2 bad input (nothing written); 130 / 143 after SIGINT / SIGTERM (every "
      "file whole; rerun to continue from OUT/.cache); 1 otherwise.\n"
      "Limits: photos (and their label images) up to 24 megapixels, other images 100; OBJ up to "
      "5,000,000 triangles, 5,000,000 vertices and 1 GiB; label images up to 65,535 regions "
      "(16-bit).\n"
      "Testing hooks (environment): PS_FAIL_AT_STAGE=<stage> makes that stage throw as it starts; "
      "PS_PAUSE_AT_STAGE=<stage> makes it wait for a signal (writing $PS_PAUSE_MARKER first).");
  cmd->callback([args] { runPipeline(*args); });
}

void runDemo() {
  const fs::path sample = fs::path(PS_SAMPLE_DIR) / "scene.json";
  if (!fs::exists(sample))
    throw NotBuiltYet("demo: the bundled sample scene (" + sample.string() +
                      ") and the run pipeline are not built yet (issue 6)");
  RunArgs args;
  args.scene = sample.string();
  args.out = "photoscene-demo";
  runPipeline(args);
}

}  // namespace ps::app

// `photoscene run SCENE.json -o OUT` and the no-argument demo.
#include <spdlog/spdlog.h>

#include <filesystem>

#include "commands.hpp"
#include "photoscene/core.hpp"
#include "photoscene/scene.hpp"

namespace ps::app {

namespace fs = std::filesystem;

namespace {

struct RunArgs {
  std::string scene, out, preset, baseline;
  int textureSize = 1024;
  int threads = 0;
};

void runPipeline(const RunArgs& args) {
  ThreadLimit limit(args.threads);
  // Everything is validated before anything is written: bad input exits 2 with no output folder.
  const Scene scene = loadScene(args.scene);
  spdlog::info("{}: valid ({} parts, {} views, {} area lights)", args.scene, scene.parts.size(),
               scene.views.size(), scene.lights.area.size());
  throw NotBuiltYet(
      "run: the pipeline that chains the stages into an output folder (issue 6) is not built yet; "
      "the stages exist as modules and samples (ps_sample_align, ps_sample_select, ps_sample_light, "
      "ps_sample_render). Nothing was written to " + args.out);
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
  cmd->add_option("--threads", args->threads, "Worker threads (default: all cores)")->check(CLI::Range(0, 1024));
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

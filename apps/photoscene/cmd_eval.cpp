// `photoscene eval OUT --scene SCENE.json`: recompute metrics.json against the photos.
#include "commands.hpp"
#include "photoscene/scene.hpp"

namespace ps::app {

void addEvalCommand(CLI::App& root) {
  auto out = std::make_shared<std::string>();
  auto scene = std::make_shared<std::string>();
  auto* cmd = root.add_subcommand("eval", "Recompute metrics.json of an output folder against the photos");
  cmd->add_option("out", *out, "Output folder of `photoscene run`")->required();
  cmd->add_option("--scene", *scene, "scene.json with the photos (and any gt/ renders)")->required();
  cmd->callback([out, scene] {
    loadScene(*scene);  // bad input first: exit 2
    throw NotBuiltYet("eval: the evaluation stage (issue 7) is not built yet");
  });
}

}  // namespace ps::app

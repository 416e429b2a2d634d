// `photoscene render OUT`: draws a twin folder (not built yet: issue 3).
#include "commands.hpp"

namespace ps::app {

void addRenderCommand(CLI::App& root) {
  auto* cmd = root.add_subcommand("render", "Render a twin folder from its views or a given camera");
  auto out = std::make_shared<std::string>();
  cmd->add_option("out", *out, "Output folder of `photoscene run`")->required();
  cmd->callback([] { throw NotBuiltYet("render: the path tracer (issue 3) is not built yet"); });
}

}  // namespace ps::app

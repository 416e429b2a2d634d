// `photoscene graphs`: the procedural material graph library (not built yet).
#include "commands.hpp"

namespace ps::app {

void addGraphsCommand(CLI::App& root) {
  auto* cmd = root.add_subcommand("graphs", "List or render the procedural material graphs");
  auto list = std::make_shared<bool>(false);
  auto render = std::make_shared<std::string>();
  cmd->add_flag("--list", *list, "One line per graph: name, category, parameter count");
  cmd->add_option("--render", *render, "Render one graph's maps");
  cmd->callback([] {
    throw NotBuiltYet("graphs: the material graph module (issue 10) is not built yet");
  });
}

}  // namespace ps::app

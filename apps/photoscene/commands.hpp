// The subcommands of `photoscene` (spec: ../shared/spec/scene-format.md section 4).
//
// Each add*Command registers one CLI11 subcommand on `root`; its callback does the work and
// reports failure by throwing: ps::InputError for bad input (exit 2), ps::NotBuiltYet for a
// stage that does not exist yet (exit 1), anything else (exit 1). main.cpp maps them.
#pragma once

#include <CLI/CLI.hpp>
#include <stdexcept>
#include <string>

namespace ps::app {

/// Thrown by a subcommand whose pipeline stages have not been built yet (exit 1, no output).
class NotBuiltYet : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Thrown by a subcommand that finished and has its own exit status (`batch`: 1 or 2 by what its
/// scenes did); main returns code() and prints nothing more.
class ExitStatus {
 public:
  explicit ExitStatus(int code) : code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

/// Registers subcommand `name` on `root` with its positional OUT (required): an output folder of
/// `photoscene run`, read into `out`. For the subcommands that work on such a folder.
inline CLI::App* addOutFolderCommand(CLI::App& root, const std::string& name,
                                     const std::string& description, std::string& out) {
  CLI::App* cmd = root.add_subcommand(name, description);
  cmd->add_option("out", out, "Output folder of `photoscene run`")->required();
  return cmd;
}

void addRunCommand(CLI::App& root);
void addRenderCommand(CLI::App& root);
void addEvalCommand(CLI::App& root);
void addGraphsCommand(CLI::App& root);
void addCheckCommand(CLI::App& root);
void addReportCommand(CLI::App& root);
void addViewCommand(CLI::App& root);
void addBatchCommand(CLI::App& root);

/// `photoscene` with no arguments: runs the bundled sample into ./photoscene-demo.
void runDemo();

}  // namespace ps::app

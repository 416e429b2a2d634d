// photoscene: photos of a room + a coarse CAD model -> a relightable digital twin.
//
// Exit status (spec section 4): 0 success; 2 bad input (the message names the file, the key and
// what was expected; nothing is written); 1 anything else, including a stage not built yet;
// 128 + the signal after SIGINT (130) or SIGTERM (143): the run stopped at a check point, every
// file written is whole, and a rerun continues from the stage cache.

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "photoscene/core.hpp"
#include "photoscene/core/memory.hpp"

int main(int argc, char** argv) {
  ps::initLogging();
  ps::reuseFreedImageMemory();  // graphs evaluated at the texture size allocate many large maps
  CLI::App app{"photoscene: photos + a coarse CAD model -> a relightable digital twin with "
               "procedural materials.\nWith no arguments, runs the bundled sample into ./photoscene-demo."};
  app.set_version_flag("--version", PS_VERSION);
  app.add_option_function<std::string>(
      "--log-level", [](const std::string& level) { ps::setLogLevel(ps::parseLogLevel(level)); },
      "trace, debug, info (default), warn, error, off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
  app.add_flag_function(
      "-q,--quiet",
      [](int64_t) {
        ps::setLogLevel(ps::LogLevel::Warn);
        ps::Progress::setDefaultMode(ps::ProgressOptions::Mode::Silent);
      },
      "Only warnings and errors; no progress bars");
  app.require_subcommand(0, 1);

  ps::app::addRunCommand(app);
  ps::app::addRenderCommand(app);
  ps::app::addEvalCommand(app);
  ps::app::addGraphsCommand(app);
  ps::app::addCheckCommand(app);
  ps::app::addReportCommand(app);
  ps::app::addViewCommand(app);
  ps::app::addBatchCommand(app);

  try {
    app.parse(argc, argv);
    if (app.get_subcommands().empty()) ps::app::runDemo();
    return 0;
  } catch (const ps::app::ExitStatus& e) {
    return e.code();
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, version or the usage error
    return code == 0 ? 0 : 2;      // a command-line mistake is bad input
  } catch (const ps::InputError& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const ps::Interrupted& e) {
    spdlog::warn(
        "interrupted (signal {}): every file written so far is whole; rerun to continue from the "
        "stage cache",
        e.signal());
    return 128 + e.signal();
  } catch (const ps::app::NotBuiltYet& e) {
    spdlog::error("{}", e.what());
    return 1;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}

// `photoscene view OUT [--port N]`: serves a twin folder on 127.0.0.1 (a small static file
// server: GET/HEAD only, nothing outside OUT) and prints the URL of its report; runs until Ctrl-C.
// Writes OUT/report.html first when it is missing.
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"

#ifdef PS_HAVE_REPORT
#include "photoscene/core/error.hpp"
#include "photoscene/report.hpp"
#endif

namespace ps::app {

void addViewCommand(CLI::App& root) {
  struct Args {
    std::string out;
    int port = 0;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = addOutFolderCommand(
      root, "view",
      "Serve a twin folder on 127.0.0.1 and print the URL of its report.html (runs until Ctrl-C)",
      a->out);
  cmd->add_option("--port", a->port, "Port on 127.0.0.1 (default 0: a free port)")
      ->check(CLI::Range(0, 65535));
#ifdef PS_HAVE_REPORT
  cmd->callback([a] {
    const std::filesystem::path out = a->out;
    if (!std::filesystem::is_directory(out)) throw InputError(a->out, "", "a twin output folder");
    if (!std::filesystem::exists(out / "report.html")) writeReport(out);
    StaticFileServer server(out, a->port);
    std::cout << server.url("report.html") << std::endl;  // flushed: scripts wait for this line
    std::cerr << "Serving " << std::filesystem::absolute(out).string() << "; press Ctrl-C to stop."
              << std::endl;
    server.serve();
  });
#else
  cmd->callback([] { throw NotBuiltYet("view: the report module is not part of this build"); });
#endif
}

}  // namespace ps::app

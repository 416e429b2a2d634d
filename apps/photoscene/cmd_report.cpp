// `photoscene report OUT`: (re)writes OUT/report.html from what the output folder holds, and
// `photoscene view OUT [--port N]`: serves the folder on 127.0.0.1 and prints the report's URL.
#include <iostream>
#include <memory>

#include "commands.hpp"

#ifdef PS_HAVE_REPORT
#include "photoscene/report.hpp"
#endif

namespace ps::app {

void addReportCommand(CLI::App& root) {
  auto out = std::make_shared<std::string>();
  auto* cmd = addOutFolderCommand(root, "report",
                                  "(Re)write OUT/report.html: photo / render / difference per "
                                  "view, a 3D viewer of the twin, the per-part table, metrics, "
                                  "loss curves",
                                  *out);
#ifdef PS_HAVE_REPORT
  auto noViewer = std::make_shared<bool>(false);
  cmd->add_flag("--no-viewer", *noViewer,
                "Leave out the 3D viewer (no viewer/ folder, no twin.gltf export)");
  cmd->callback([out, noViewer] {
    ReportOptions o;
    o.viewer = !*noViewer;
    writeReport(*out, o);
    std::cout << (std::filesystem::path(*out) / "report.html").string() << std::endl;
  });
#else
  cmd->callback([] { throw NotBuiltYet("report: the report module is not part of this build"); });
#endif
}

}  // namespace ps::app

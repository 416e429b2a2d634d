// Where photoscene's run-time data (the material-graph library, the report's 3D viewer) is found
// when photoscene is used from an installed tree rather than from its build tree.
//
// `cmake --install` puts the data under <prefix>/share/photoscene/<name> (graphs/, viewer/). A
// program finds it without the source tree, in this order:
//   1. next to the running program: <folder of the executable>/../share/photoscene/<name>
//      (the installed `photoscene` command, or any program installed into the same prefix;
//      the path from bin to share is the one GNUInstallDirs configured)
//   2. `buildTreeFolder`: the folder a program of the build tree uses (compiled in by the module)
//   3. <CMAKE_INSTALL_PREFIX configured at build time>/share/photoscene/<name>
//
//   fs::path graphs = ps::findDataFolder("graphs", PS_GRAPH_LIBRARY_DIR);
//   if (graphs.empty()) ... nothing installed, no build tree
#pragma once

#include <filesystem>
#include <string>

namespace ps {

/// The folder of the running executable (from /proc/self/exe); empty when it cannot be read.
std::filesystem::path executableFolder();

/// The first existing folder of the list above, or empty when none exists.
std::filesystem::path findDataFolder(const std::string& name,
                                     const std::filesystem::path& buildTreeFolder = {});

}  // namespace ps

// ps::findDataFolder: run-time data of an installed photoscene.
#include "photoscene/core/data_folder.hpp"

#include <system_error>

// Compiled in by modules/core/CMakeLists.txt (GNUInstallDirs): share/photoscene relative to bin,
// and the absolute folder under the configured install prefix.
#ifndef PS_DATA_FROM_BIN
#define PS_DATA_FROM_BIN "../share/photoscene"
#endif
#ifndef PS_INSTALL_DATA_DIR
#define PS_INSTALL_DATA_DIR ""
#endif

namespace ps {

namespace fs = std::filesystem;

fs::path executableFolder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty()) return {};
  return exe.parent_path();
}

fs::path findDataFolder(const std::string& name, const fs::path& buildTreeFolder) {
  std::error_code ec;
  const auto isDir = [&](const fs::path& p) { return !p.empty() && fs::is_directory(p, ec); };
  if (const fs::path bin = executableFolder(); !bin.empty()) {
    const fs::path beside = (bin / PS_DATA_FROM_BIN / name).lexically_normal();
    if (isDir(beside)) return beside;
  }
  if (isDir(buildTreeFolder)) return buildTreeFolder;
  if (const std::string installed = PS_INSTALL_DATA_DIR; !installed.empty())
    if (const fs::path p = fs::path(installed) / name; isDir(p)) return p;
  return {};
}

}  // namespace ps

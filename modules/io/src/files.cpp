#include "photoscene/io/files.hpp"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <sstream>

#include "photoscene/core/error.hpp"

namespace ps::io {

fs::path temporaryPathFor(const fs::path& path) {
  static std::atomic<int> counter{0};
  const std::string name = "." + path.stem().string() + ".tmp-" + std::to_string(getpid()) + "-" +
                           std::to_string(counter++) + path.extension().string();
  return path.parent_path() / name;
}

void writeAtomically(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  const fs::path tmp = temporaryPathFor(path);
  try {
    write(tmp);
    fs::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void writeTextFile(const fs::path& path, const std::string& text) {
  writeAtomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    PS_Check(out.good(), "cannot open " << tmp << " for writing");
    out << text;
    out.flush();
    PS_Check(out.good(), "cannot write " << tmp);
  });
}

std::string readTextFile(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path.string(), "", "file not found");
  if (fs::is_directory(path, ec)) throw InputError(path.string(), "", "expected a file, found a folder");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open the file for reading");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

TempDir::TempDir(const std::string& prefix) {
  static std::atomic<int> counter{0};
  const fs::path base = fs::temp_directory_path();
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const fs::path candidate = base / (prefix + "-" + std::to_string(getpid()) + "-" +
                                       std::to_string(counter++));
    std::error_code ec;
    if (fs::create_directory(candidate, ec)) {
      path_ = candidate;
      return;
    }
  }
  PS_Check(false, "cannot create a temporary folder under " << base);
}

TempDir::~TempDir() {
  std::error_code ec;
  if (!path_.empty()) fs::remove_all(path_, ec);
}

}  // namespace ps::io

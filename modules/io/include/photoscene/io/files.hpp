// Whole-or-nothing file output: every output file is written to a temporary name in the same
// folder and renamed into place, so a reader (or a crash) never sees a half-written file.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace ps::io {

namespace fs = std::filesystem;

/// A temporary sibling of `path` that keeps its extension (".name.tmp-<pid>-<n>.ext").
fs::path temporaryPathFor(const fs::path& path);

/// Calls write(tmp) with a temporary path next to `path`, then renames tmp onto `path`.
/// On any exception the temporary file is removed and the exception propagates.
void writeAtomically(const fs::path& path, const std::function<void(const fs::path&)>& write);

/// Writes text (UTF-8) atomically.
void writeTextFile(const fs::path& path, const std::string& text);
/// Reads a whole file; throws ps::InputError naming the file when it is missing or unreadable.
std::string readTextFile(const fs::path& path);

/// A fresh folder under the system temp folder, removed (recursively) on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "photoscene");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  fs::path operator/(const fs::path& p) const { return path_ / p; }

 private:
  fs::path path_;
};

}  // namespace ps::io

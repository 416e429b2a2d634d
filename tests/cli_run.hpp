// Running the `photoscene` command from a test: what tests/test_cli.cpp and
// tests/test_batch_cli.cpp share. PHOTOSCENE_BIN and PS_BINARY_DIR come from tests/CMakeLists.txt.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace ps::cli_test {

struct Result {
  int exitCode = -1;
  std::string output;  // stdout + stderr
};

/// Every run shares the exemplar-bank cache of the build tree (built once, by whichever test is
/// first); a cache the caller set already wins.
inline const int kCacheEnv = setenv("PS_CACHE_DIR", PS_BINARY_DIR "/photoscene-cache", 0);

/// `photoscene ARGS` through the shell, stdout and stderr together.
inline Result runPhotoscene(const std::string& args) {
  const std::string cmd = std::string(PHOTOSCENE_BIN) + " " + args + " 2>&1";
  Result r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
  const int status = pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace ps::cli_test

// Running the `photoscene` command from a test: what tests/test_cli.cpp and
// tests/test_batch_cli.cpp share. PHOTOSCENE_BIN and PS_BINARY_DIR come from tests/CMakeLists.txt.
#pragma once

#include <cstdlib>
#include <string>

#include "run_command.hpp"

namespace ps::cli_test {

/// Every run shares the exemplar-bank cache of the build tree (built once, by whichever test is
/// first); a cache the caller set already wins.
inline const int kCacheEnv = setenv("PS_CACHE_DIR", PS_BINARY_DIR "/photoscene-cache", 0);

/// `photoscene ARGS` through the shell, stdout and stderr together.
inline Result runPhotoscene(const std::string& args) {
  return runCommand(std::string(PHOTOSCENE_BIN) + " " + args);
}

inline bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace ps::cli_test

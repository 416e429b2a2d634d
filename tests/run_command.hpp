// Running a shell command from a test, its exit code and its output (stdout and stderr
// together): what tests/cli_run.hpp and tests/test_samples.cpp share.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace ps::cli_test {

struct Result {
  int exitCode = -1;
  std::string output;  // stdout + stderr
};

/// `cmd` through the shell, stdout and stderr together; exit code -1 when it did not exit.
inline Result runCommand(const std::string& cmd) {
  Result r;
  FILE* pipe = popen((cmd + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
  const int status = pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace ps::cli_test

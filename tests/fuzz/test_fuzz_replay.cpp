// Replays the fuzz seed corpora and every kept finding (tests/fuzz/regressions/<target>/)
// through the same entry points the fuzzers use: each file must be accepted or refused with
// ps::InputError, nothing else.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz_entries.hpp"

namespace {

namespace fs = std::filesystem;

std::vector<uint8_t> readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void replay(const std::string& kind) {
  int files = 0, accepted = 0;
  for (const std::string& target : ps::fuzz::targets()) {
    const fs::path dir = fs::path(PS_FUZZ_DIR) / kind / target;
    if (!fs::exists(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir)) {
      if (!e.is_regular_file() || e.path().filename().string()[0] == '.') continue;
      const auto bytes = readBytes(e.path());
      ++files;
      try {
        accepted += ps::fuzz::run(target, bytes.data(), bytes.size());
      } catch (const std::exception& ex) {
        ADD_FAILURE() << target << " " << e.path() << ": " << ex.what();
      }
    }
  }
  std::printf("%s: %d files, %d accepted\n", kind.c_str(), files, accepted);
  if (kind == "corpus") EXPECT_GT(accepted, 0);  // the seeds include valid files
}

TEST(Fuzz_Replay, seed_corpora_are_accepted_or_refused_cleanly) { replay("corpus"); }
TEST(Fuzz_Replay, kept_findings_no_longer_fail) { replay("regressions"); }

}  // namespace

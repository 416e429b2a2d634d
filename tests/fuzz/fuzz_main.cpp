// libFuzzer driver for one target, chosen at compile time (PS_FUZZ_TARGET).
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "fuzz_entries.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    ps::fuzz::run(PS_FUZZ_TARGET, data, size);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "finding: %s threw %s\n", PS_FUZZ_TARGET, e.what());
    std::abort();
  }
  return 0;
}

#include "photoscene/core/rng.hpp"

#include <cmath>

namespace ps {

uint32_t Rng::uniformInt(uint32_t n) {
  if (n == 0) return 0;
  uint64_t m = static_cast<uint64_t>(nextU32()) * n;
  uint32_t low = static_cast<uint32_t>(m);
  if (low < n) {
    const uint32_t threshold = (~n + 1u) % n;
    while (low < threshold) {
      m = static_cast<uint64_t>(nextU32()) * n;
      low = static_cast<uint32_t>(m);
    }
  }
  return static_cast<uint32_t>(m >> 32);
}

float Rng::normal() {
  // Box-Muller with u1 in (0, 1] so the log is finite.
  const double u1 = 1.0 - uniformDouble();
  const double u2 = uniformDouble();
  return static_cast<float>(std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2));
}

Hasher& Hasher::add(const void* data, size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    h_ ^= p[i];
    h_ *= 0x100000001b3ULL;
  }
  return *this;
}

}  // namespace ps

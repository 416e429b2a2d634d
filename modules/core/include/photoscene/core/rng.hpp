// Seeded random numbers: PCG32 (O'Neill 2014) with independent streams.
//
// No global generator: every random choice takes a seed from its caller. For parallel work,
// derive one generator per task with split(taskIndex) so results do not depend on scheduling.
//
//   ps::Rng rng(seed);
//   float u = rng.uniform();              // [0, 1)
//   ps::Rng pixelRng = rng.split(y * width + x);
#pragma once

#include <cstdint>
#include <string_view>
#include <type_traits>
#include <cstddef>

namespace ps {

/// SplitMix64 finalizer: a strong 64-bit mix (hashing seeds and keys).
inline uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class Rng {
 public:
  explicit Rng(uint64_t seed = 0, uint64_t stream = 0) { seed_(seed, stream); }

  uint32_t nextU32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
  }
  uint64_t nextU64() { return (static_cast<uint64_t>(nextU32()) << 32) | nextU32(); }
  /// Uniform in [0, 1), 24 bits of resolution (never returns 1).
  float uniform() { return static_cast<float>(nextU32() >> 8) * 0x1p-24f; }
  /// Uniform in [0, 1), 53 bits of resolution.
  double uniformDouble() { return static_cast<double>(nextU64() >> 11) * 0x1p-53; }
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), unbiased (Lemire's method). n must be > 0.
  uint32_t uniformInt(uint32_t n);
  /// Standard normal (Box-Muller).
  float normal();

  /// An independent generator derived from this one's seed and `key` (does not advance this).
  Rng split(uint64_t key) const { return Rng(mix64(seedKey_ ^ mix64(key + 1)), key); }

 private:
  void seed_(uint64_t seed, uint64_t stream) {
    seedKey_ = mix64(seed ^ mix64(stream));
    state_ = 0;
    inc_ = (mix64(stream) << 1u) | 1u;
    nextU32();
    state_ += mix64(seed);
    nextU32();
  }
  uint64_t state_ = 0, inc_ = 1, seedKey_ = 0;
};

/// 64-bit FNV-1a hash of bytes, finished with mix64: content keys for caches.
class Hasher {
 public:
  Hasher& add(const void* data, size_t size);
  Hasher& add(std::string_view s) {
    add(s.size());
    return add(s.data(), s.size());
  }
  template <typename T>
  Hasher& add(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    return add(&value, sizeof(T));
  }
  uint64_t digest() const { return mix64(h_); }

 private:
  uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace ps

// Per-pixel low-discrepancy sample points for the path tracer: Owen-scrambled Sobol with
// nested uniform index shuffling (Burley 2020, "Practical Hash-based Owen Scrambling"), padded
// per dimension.
//
// Every dimension d (a 1D value, or a 2D pair) of sample `index` in pixel `pixel` is
//   i' = nestedUniformScramble(index, h(seed, pixel, d))            (a per-pixel, per-dimension
//   shuffle) x  = nestedUniformScramble(sobol_0(i'), h(seed, pixel, d, 0))   (and sobol_1 for y)
// so the first 2^k samples of each 2D pair are a (0, k, 2)-net (every elementary interval of
// area 2^-k holds exactly one point: stratified in x, in y and in every 2^a x 2^b grid with
// a + b = k), each 1D value is stratified into 2^k equal intervals, and different dimensions,
// pixels and seeds are decorrelated by independent hashes (no regular patterns across pixels).
// Non-power-of-two sample counts are prefixes of the same sequence (still well spread).
//
// The state is the pixel and the sample index only: the same points on any thread count.
//
//   ps::SobolSampler s(seed, y * width + x);
//   for (int i = 0; i < spp; ++i) {
//     s.startSample(i);
//     const ps::Vec2f pixel = s.get2D(0);   // dimensions are fixed per use (0-1 pixel, ...)
//     const float lightPick = s.get1D(2);
//   }
#pragma once

#include <cstdint>

#include "photoscene/core/math.hpp"
#include "photoscene/core/rng.hpp"

namespace ps {

namespace sobol {

inline uint32_t reverseBits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

/// Laine-Karras style permutation with Vegdahl's constants: each output bit depends only on
/// the input bits at or below it.
inline uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

/// Owen scrambling of a 32-bit fixed-point value (bit 31 = 1/2): each bit is flipped by a
/// hash of the bits above it.
inline uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) {
  return reverseBits(laineKarrasPermutation(reverseBits(x), seed));
}

/// Sobol dimension 0 (van der Corput), 32-bit fixed point.
inline uint32_t dim0(uint32_t i) {
  return reverseBits(i);
}

/// nestedUniformScramble(dim0(i), seed) with the two bit reversals that cancel left out (the
/// same value: dim0 reverses the bits and the scramble reverses them back first).
inline uint32_t scrambledDim0(uint32_t i, uint32_t seed) {
  return reverseBits(laineKarrasPermutation(i, seed));
}

/// Sobol dimension 1 (generator: the Pascal matrix mod 2), 32-bit fixed point.
inline uint32_t dim1(uint32_t i) {
  uint32_t x = 0, v = 0x80000000u;
  for (; i; i >>= 1) {
    x ^= (0u - (i & 1u)) & v;
    v ^= v >> 1;
  }
  return x;
}

/// nestedUniformScramble(dim1(i), seed) without reversing dim1's bits: the generator's columns
/// are built bit-reversed instead (rev(v >> 1) = rev(v) << 1), the same value.
inline uint32_t scrambledDim1(uint32_t i, uint32_t seed) {
  uint32_t x = 0, v = 1u;
  for (; i; i >>= 1) {
    x ^= (0u - (i & 1u)) & v;
    v ^= v << 1;
  }
  return reverseBits(laineKarrasPermutation(x, seed));
}

inline float toUnit(uint32_t x) {
  return std::min(static_cast<float>(x >> 8) * 0x1p-24f, 0x1.fffffep-1f);
}

}  // namespace sobol

/// Low-discrepancy points of one pixel (see the file comment).
class SobolSampler {
 public:
  /// @param seed   the render's seed
  /// @param pixel  a key unique per pixel (e.g. y * width + x)
  SobolSampler(uint64_t seed, uint64_t pixel)
      : key_(mix64(mix64(seed) ^ mix64(pixel + 0x51ed270b27a3f1c5ULL))) {}

  void startSample(uint32_t index) { index_ = index; }
  uint32_t sampleIndex() const { return index_; }

  /// Value of dimension `dim` of the current sample, in [0, 1).
  float get1D(uint32_t dim) const {
    const uint64_t h = mix64(key_ + dim);
    const uint32_t i = sobol::nestedUniformScramble(index_, static_cast<uint32_t>(h));
    return sobol::toUnit(sobol::scrambledDim0(i, static_cast<uint32_t>(h >> 32)));
  }
  /// The 2D pair of dimension `dim` (its own dimension: independent of get1D(dim)), in [0, 1)^2.
  Vec2f get2D(uint32_t dim) const {
    const uint64_t h = mix64(key_ + dim + 0x9e3779b97f4a7c15ULL);
    const uint32_t i = sobol::nestedUniformScramble(index_, static_cast<uint32_t>(h));
    const uint64_t h2 = mix64(h);
    return Vec2f(sobol::toUnit(sobol::scrambledDim0(i, static_cast<uint32_t>(h2))),
                 sobol::toUnit(sobol::scrambledDim1(i, static_cast<uint32_t>(h2 >> 32))));
  }

 private:
  uint64_t key_;
  uint32_t index_ = 0;
};

/// The same interface over independent random numbers (for callers that hold an Rng).
class IndependentSampler {
 public:
  explicit IndependentSampler(Rng& rng) : rng_(rng) {}
  float get1D(uint32_t) const { return rng_.uniform(); }
  Vec2f get2D(uint32_t) const {
    const float a = rng_.uniform();
    return Vec2f(a, rng_.uniform());
  }

 private:
  Rng& rng_;
};

}  // namespace ps

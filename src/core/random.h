// Deterministic random numbers. Every stream is keyed by what it is for —
// (scene seed, frame, pixel, sample, purpose) — so results do not depend on
// thread count or scheduling: the same key always gives the same sequence.
#pragma once

#include <cmath>
#include <cstdint>

namespace lt {

// splitmix64 finaliser: a bijective 64-bit mix.
constexpr uint64_t Mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Hashes several 64-bit words into one key.
constexpr uint64_t HashKey(uint64_t a, uint64_t b = 0, uint64_t c = 0, uint64_t d = 0, uint64_t e = 0) {
  uint64_t h = Mix64(a);
  h = Mix64(h ^ b);
  h = Mix64(h ^ c);
  h = Mix64(h ^ d);
  return Mix64(h ^ e);
}

// PCG32 (O'Neill 2014): small state, good statistics, seekable by key.
class Rng {
 public:
  explicit Rng(uint64_t key) : state_(0), inc_((Mix64(key ^ 0xda3e39cb94b95bdbull) << 1u) | 1u) {
    NextU32();
    state_ += Mix64(key);
    NextU32();
  }
  // The stream for one (seed, frame, pixel, sample, purpose).
  static Rng For(uint64_t seed, uint64_t frame, uint64_t pixel, uint64_t sample, uint64_t purpose = 0) {
    return Rng(HashKey(seed, frame, pixel, sample, purpose));
  }

  uint32_t NextU32() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
  }
  // Uniform in [0, 1).
  float NextFloat() { return float(NextU32() >> 8) * 0x1p-24f; }
  double NextDouble() {
    uint64_t hi = NextU32(), lo = NextU32();
    return double(((hi << 32) | lo) >> 11) * 0x1p-53;
  }
  // Standard normal (Box–Muller; one value per call for simplicity).
  double NextGaussian() {
    double u1 = 1.0 - NextDouble();  // (0, 1]
    double u2 = NextDouble();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  uint64_t state_;
  uint64_t inc_;
};

}  // namespace lt

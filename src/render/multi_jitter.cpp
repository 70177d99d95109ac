#include "render/multi_jitter.h"

#include <cmath>

namespace lt {

namespace {

// A permutation of [0, l) chosen by p (Kensler's hash-based permute).
uint32_t Permute(uint32_t i, uint32_t l, uint32_t p) {
  // [0, 1) has one permutation: the loop below would give i = 0 and return
  // (0 + p) % 1 = 0 (the single column of a batch of 2 or 3 samples).
  if (l == 1) return 0;
  uint32_t w = l - 1;
  w |= w >> 1;
  w |= w >> 2;
  w |= w >> 4;
  w |= w >> 8;
  w |= w >> 16;
  do {
    i ^= p;
    i *= 0xe170893du;
    i ^= p >> 16;
    i ^= (i & w) >> 4;
    i ^= p >> 8;
    i *= 0x0929eb3fu;
    i ^= p >> 23;
    i ^= (i & w) >> 1;
    i *= 1u | p >> 27;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303u;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3u;
    i ^= (i & w) >> 2;
    i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5;
  } while (i >= l);
  return (i + p) % l;
}

// A number in [0, 1) from (i, p).
double RandUnit(uint32_t i, uint32_t p) {
  i ^= p;
  i ^= i >> 17;
  i ^= i >> 10;
  i *= 0xb36534e5u;
  i ^= i >> 12;
  i ^= i >> 21;
  i *= 0x93fc4795u;
  i ^= 0xdf6e307fu;
  i ^= i >> 17;
  i *= 1u | p >> 18;
  return i * (1.0 / 4294967296.0);
}

}  // namespace

Eigen::Vector2d MultiJitter2D(uint32_t s, uint32_t n, uint32_t pattern) {
  // One sample: one cell, s = sx = sy = 0, so the point is (jx, jy) exactly
  // (the general form's sums and divisions by 1 leave it as it is).
  if (n == 1) return {RandUnit(0, pattern * 0x967a889bu), RandUnit(0, pattern * 0x368cc8b7u)};
  const uint32_t m = std::max(1u, uint32_t(std::sqrt(double(n))));  // columns
  const uint32_t rows = (n + m - 1) / m;
  // The points are N of the m x rows cells, a different subset per pattern when
  // N < m x rows, so that every cell is equally likely over patterns (unbiased).
  s = Permute(s, m * rows, pattern * 0x51633e2du);
  const uint32_t sx = Permute(s % m, m, pattern * 0x68bc21ebu);
  const uint32_t sy = Permute(s / m, rows, pattern * 0x02e5be93u);
  const double jx = RandUnit(s, pattern * 0x967a889bu);
  const double jy = RandUnit(s, pattern * 0x368cc8b7u);
  return {(s % m + (sy + jx) / rows) / m, (s / m + (sx + jy) / m) / rows};
}

}  // namespace lt

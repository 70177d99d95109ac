// Correlated multi-jittered sampling (Kensler 2013, "Correlated Multi-Jittered
// Sampling", Pixar Technical Memo 13-01): N points in the unit square that are
// jittered-stratified on a sqrt(N) grid and, at the same time, one per column
// and one per row of an N x N grid (N-rooks). The second property is what a thin
// stripe needs: a stripe one pixel wide running along the rows is sampled at N
// distinct heights within the pixel, not sqrt(N). Any N works, not only squares.
// Deterministic in (s, N, pattern); a different pattern per pixel decorrelates
// pixels. For N = m x rows (m = floor(sqrt(N))), the N-rooks property is exact;
// otherwise the N points take N of the m x rows cells, a subset chosen by the
// pattern so that the points stay uniform over patterns.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace lt {

// The s-th of N points (0 <= s < N) of the pattern, in [0, 1)^2.
Eigen::Vector2d MultiJitter2D(uint32_t s, uint32_t n, uint32_t pattern);

}  // namespace lt

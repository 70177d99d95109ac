#include "render/multi_jitter.h"

#include <gtest/gtest.h>

#include <set>

namespace lt {
namespace {

// For N = m x rows points: one point in each of the N columns and N rows of the
// N x N grid (N-rooks) and one in each cell of the m x rows grid (jittered).
TEST(MultiJitter, NRooksAndJitteredStrata) {
  for (uint32_t pattern : {0u, 1u, 12345u, 0xdeadbeefu}) {
    for (auto [m, rows] : {std::pair{1u, 1u}, {2u, 2u}, {3u, 3u}, {4u, 4u}, {8u, 8u}, {3u, 4u}}) {
      const uint32_t n = m * rows;
      std::set<uint32_t> cols_n, rows_n, cells;
      for (uint32_t s = 0; s < n; ++s) {
        Eigen::Vector2d p = MultiJitter2D(s, n, pattern);
        ASSERT_GE(p.x(), 0.0);
        ASSERT_LT(p.x(), 1.0);
        ASSERT_GE(p.y(), 0.0);
        ASSERT_LT(p.y(), 1.0);
        cols_n.insert(uint32_t(p.x() * n));
        rows_n.insert(uint32_t(p.y() * n));
        cells.insert(uint32_t(p.x() * m) + m * uint32_t(p.y() * rows));
        EXPECT_EQ(p, MultiJitter2D(s, n, pattern));  // deterministic
      }
      EXPECT_EQ(cols_n.size(), n) << "m " << m << " rows " << rows;
      EXPECT_EQ(rows_n.size(), n) << "m " << m << " rows " << rows;
      EXPECT_EQ(cells.size(), n) << "m " << m << " rows " << rows;
    }
  }
}

// Over many patterns the points are uniform: the mean of x, y and xy over all
// points of 4000 patterns of 5 points is 1/2, 1/2, 1/4 within 5 standard errors
// (sd of a uniform is 0.29, of xy 0.22; 20000 points).
TEST(MultiJitter, UniformOverPatterns) {
  double sx = 0, sy = 0, sxy = 0;
  int count = 0;
  for (uint32_t pattern = 0; pattern < 4000; ++pattern) {
    for (uint32_t s = 0; s < 5; ++s) {
      Eigen::Vector2d p = MultiJitter2D(s, 5, pattern * 2654435761u);
      sx += p.x(), sy += p.y(), sxy += p.x() * p.y();
      ++count;
    }
  }
  const double se = 0.29 / std::sqrt(double(count));
  EXPECT_NEAR(sx / count, 0.5, 5 * se);
  EXPECT_NEAR(sy / count, 0.5, 5 * se);
  EXPECT_NEAR(sxy / count, 0.25, 5 * 0.22 / std::sqrt(double(count)));
}

}  // namespace
}  // namespace lt

#include "core/random.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lt {
namespace {

TEST(Rng, SameKeySameSequence) {
  Rng a = Rng::For(1, 2, 3, 4), b = Rng::For(1, 2, 3, 4);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.NextU32(), b.NextU32());
}

TEST(Rng, NeighbouringKeysDiffer) {
  Rng a = Rng::For(1, 0, 0, 0), b = Rng::For(1, 0, 1, 0);
  int same = 0;
  for (int i = 0; i < 100; ++i) same += a.NextU32() == b.NextU32();
  EXPECT_LT(same, 3);
}

TEST(Rng, UniformAndGaussianMoments) {
  // 200k samples: standard errors are 0.0006 (mean of U), 0.0022 (mean of N),
  // 0.0032 (variance of N); bounds are about 5 standard errors.
  Rng r(42);
  const int n = 200000;
  double su = 0, sg = 0, sg2 = 0;
  for (int i = 0; i < n; ++i) {
    float u = r.NextFloat();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    su += u;
    double g = r.NextGaussian();
    sg += g;
    sg2 += g * g;
  }
  EXPECT_NEAR(su / n, 0.5, 0.003);
  EXPECT_NEAR(sg / n, 0.0, 0.011);
  EXPECT_NEAR(sg2 / n, 1.0, 0.016);
}

}  // namespace
}  // namespace lt

// Goodness-of-fit helpers for the sampling tests: Pearson's chi-square over
// histogram cells, and the same for direction samplers on the sphere with the
// expected counts integrated numerically from the claimed pdf.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <vector>

#include "core/random.h"

namespace lt::test {

struct ChiSquare {
  double statistic = 0;
  int dof = 0;
  // Wilson–Hilferty normal score of the statistic: about N(0, 1) when the
  // samples follow the expected distribution. The tests require z < 4, a
  // one-sided false-failure probability of 3e-5 (and the seeds are fixed).
  double z = 0;
  // Samples that fell in cells where the expected count is zero: must be 0.
  double impossible = 0;
};

// Cells whose expected count is below 5 are pooled into one cell (the usual
// validity condition of the chi-square approximation).
inline ChiSquare PearsonChiSquare(const std::vector<double>& observed, const std::vector<double>& expected) {
  ChiSquare r;
  double pooled_obs = 0, pooled_exp = 0;
  int cells = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] <= 0) {
      r.impossible += observed[i];
    } else if (expected[i] < 5) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
    } else {
      const double d = observed[i] - expected[i];
      r.statistic += d * d / expected[i];
      ++cells;
    }
  }
  if (pooled_exp > 0) {
    const double d = pooled_obs - pooled_exp;
    r.statistic += d * d / pooled_exp;
    ++cells;
  }
  r.dof = cells - 1;
  const double k = r.dof;
  r.z = (std::cbrt(r.statistic / k) - (1.0 - 2.0 / (9.0 * k))) / std::sqrt(2.0 / (9.0 * k));
  return r;
}

struct DirectionTest {
  ChiSquare chi;
  double pdf_integral = 0;  // numerical integral of the pdf over the sphere
  double max_norm_error = 0;  // max | |w| - 1 | over the samples
};

// Histogram of `n` directions from `sample(u1, u2)` on nz x nphi cells, uniform
// in z = cos(theta) and phi (equal solid angle dz dphi each), against counts
// from `pdf(w)` integrated by the midpoint rule on sub x sub points per cell.
inline DirectionTest TestDirections(const std::function<Eigen::Vector3f(float, float)>& sample,
                                    const std::function<double(const Eigen::Vector3f&)>& pdf, int n,
                                    uint64_t seed, int nz = 20, int nphi = 40, int sub = 8) {
  DirectionTest t;
  std::vector<double> observed(size_t(nz) * nphi, 0.0), expected(size_t(nz) * nphi, 0.0);
  Rng rng(seed);
  for (int i = 0; i < n; ++i) {
    const float u1 = rng.NextFloat(), u2 = rng.NextFloat();
    const Eigen::Vector3f w = sample(u1, u2);
    t.max_norm_error = std::max(t.max_norm_error, std::abs(double(w.norm()) - 1.0));
    const double z = std::clamp(double(w.z()), -1.0, 1.0);
    double phi = std::atan2(double(w.y()), double(w.x()));
    if (phi < 0) phi += 2 * M_PI;
    const int iz = std::min(nz - 1, int((z + 1) * 0.5 * nz));
    const int ip = std::min(nphi - 1, int(phi / (2 * M_PI) * nphi));
    observed[size_t(iz) * nphi + ip] += 1;
  }
  const double dz = 2.0 / nz, dphi = 2 * M_PI / nphi;
  for (int iz = 0; iz < nz; ++iz) {
    for (int ip = 0; ip < nphi; ++ip) {
      double integral = 0;
      for (int a = 0; a < sub; ++a) {
        for (int b = 0; b < sub; ++b) {
          const double z = -1 + dz * (iz + (a + 0.5) / sub);
          const double phi = dphi * (ip + (b + 0.5) / sub);
          const double s = std::sqrt(std::max(0.0, 1 - z * z));
          integral += pdf(Eigen::Vector3f(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)));
        }
      }
      integral *= dz * dphi / (sub * sub);
      t.pdf_integral += integral;
      // A cell whose support the midpoints miss (a sliver cut by the edge of
      // the support) is impossible only if the pdf also vanishes on its edges.
      bool support = integral > 0;
      for (int a = 0; a <= sub && !support; ++a) {
        for (int b = 0; b <= sub && !support; ++b) {
          const double z = -1 + dz * (iz + double(a) / sub), phi = dphi * (ip + double(b) / sub);
          const double s = std::sqrt(std::max(0.0, 1 - z * z));
          support = pdf(Eigen::Vector3f(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z))) > 0;
        }
      }
      // Such slivers get a token expectation so that they are pooled, not impossible.
      expected[size_t(iz) * nphi + ip] = integral > 0 ? integral * n : (support ? 1e-9 : 0.0);
    }
  }
  t.chi = PearsonChiSquare(observed, expected);
  return t;
}

}  // namespace lt::test

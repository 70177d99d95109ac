#include "render/sampling.h"

#include <gtest/gtest.h>

#include <cmath>

#include "chi_square.h"
#include "core/random.h"
#include "render/microfacet.h"

namespace lt {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3f;

// Samples per direction test: 100k over 800 cells gives about 125 expected per
// cell where the density is flat, enough for the chi-square approximation, and
// keeps the suite fast under sanitizers.
constexpr int kSamples = 100000;

// Every direction test checks: the claimed pdf integrates to 1 over the sphere
// (midpoint rule, 8x8 points per cell; 2e-3 covers the quadrature error at the
// edge of a cone), the samples are unit vectors (float rounding: 1e-5), and the
// histogram matches the pdf (chi-square score z < 4, see chi_square.h).
void ExpectMatches(const test::DirectionTest& t, double integral_tol = 2e-3) {
  EXPECT_NEAR(t.pdf_integral, 1.0, integral_tol);
  EXPECT_LT(t.max_norm_error, 1e-5);
  EXPECT_LT(t.chi.z, 4.0) << "chi2 " << t.chi.statistic << " dof " << t.chi.dof;
  EXPECT_EQ(t.chi.impossible, 0);
}

TEST(Sampling, OrthonormalBasisIsRightHandedAndOrthonormal) {
  Rng rng(7);
  std::vector<Vector3f> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0, 0, -0.0f}};
  normals[4] = Vector3f(1e-7f, 0, -1).normalized();  // near the branch point of older methods
  for (int i = 0; i < 1000; ++i) normals.push_back(SampleUniformSphere(rng.NextFloat(), rng.NextFloat()));
  for (const Vector3f& n : normals) {
    Vector3f b1, b2;
    OrthonormalBasis(n, &b1, &b2);
    EXPECT_NEAR(b1.norm(), 1.0f, 1e-5f);
    EXPECT_NEAR(b2.norm(), 1.0f, 1e-5f);
    EXPECT_NEAR(b1.dot(b2), 0.0f, 1e-5f);
    EXPECT_NEAR(b1.dot(n), 0.0f, 1e-5f);
    EXPECT_NEAR(b2.dot(n), 0.0f, 1e-5f);
    EXPECT_LT((b1.cross(b2) - n).norm(), 2e-5f);
    const Frame f = Frame::FromNormal(n);
    const Vector3f w(0.3f, -0.5f, 0.81f);
    EXPECT_LT((f.ToWorld(f.ToLocal(w)) - w).norm(), 1e-5f);
    EXPECT_NEAR(f.ToLocal(n).z(), 1.0f, 1e-5f);
  }
}

TEST(Sampling, CosineHemisphere) {
  ExpectMatches(test::TestDirections([](float a, float b) { return SampleCosineHemisphere(a, b); },
                                     [](const Vector3f& w) { return CosineHemispherePdf(w.z()); }, kSamples, 1));
}

TEST(Sampling, UniformHemisphere) {
  ExpectMatches(test::TestDirections([](float a, float b) { return SampleUniformHemisphere(a, b); },
                                     [](const Vector3f& w) { return w.z() >= 0 ? UniformHemispherePdf() : 0.0f; },
                                     kSamples, 2));
}

TEST(Sampling, UniformSphere) {
  ExpectMatches(test::TestDirections([](float a, float b) { return SampleUniformSphere(a, b); },
                                     [](const Vector3f&) { return UniformSpherePdf(); }, kSamples, 3));
}

TEST(Sampling, UniformCone) {
  for (float cos_max : {0.8f, 0.0f, -0.5f}) {
    SCOPED_TRACE(cos_max);
    ExpectMatches(
        test::TestDirections([&](float a, float b) { return SampleUniformCone(a, b, cos_max); },
                             [&](const Vector3f& w) { return w.z() >= cos_max ? UniformConePdf(cos_max) : 0.0f; },
                             kSamples, 4));
  }
  // A narrow cone (0.1 mrad) keeps unit directions inside the cone.
  const float cos_tiny = std::cos(1e-4f);
  Rng rng(5);
  for (int i = 0; i < 1000; ++i) {
    const Vector3f w = SampleUniformCone(rng.NextFloat(), rng.NextFloat(), cos_tiny);
    EXPECT_NEAR(w.norm(), 1.0f, 1e-6f);
    EXPECT_LE(std::sqrt(w.x() * w.x() + w.y() * w.y()), 1.0001e-4f);
  }
}

TEST(Sampling, ConcentricDiskIsUniform) {
  // Cells of equal area: 10 rings uniform in r^2 times 16 sectors, 100k samples
  // (625 expected per cell).
  const int nr = 10, np = 16, n = 100000;
  std::vector<double> observed(nr * np, 0.0), expected(nr * np, double(n) / (nr * np));
  Rng rng(11);
  for (int i = 0; i < n; ++i) {
    const Vector2f p = SampleConcentricDisk(rng.NextFloat(), rng.NextFloat());
    ASSERT_LE(p.squaredNorm(), 1.0f + 1e-6f);
    double phi = std::atan2(double(p.y()), double(p.x()));
    if (phi < 0) phi += 2 * M_PI;
    const int ir = std::min(nr - 1, int(p.squaredNorm() * nr));
    const int ip = std::min(np - 1, int(phi / (2 * M_PI) * np));
    observed[ir * np + ip] += 1;
  }
  const test::ChiSquare chi = test::PearsonChiSquare(observed, expected);
  EXPECT_LT(chi.z, 4.0) << chi.statistic;
  EXPECT_EQ(SampleConcentricDisk(0.5f, 0.5f), Vector2f(0, 0));
}

TEST(Sampling, TriangleIsUniform) {
  // Grid of n x n squares over (b0, b1); squares below the diagonal lie inside
  // the triangle, squares on it are cut exactly in half. 100k samples.
  const int g = 12, n = 100000;
  std::vector<double> observed(g * g, 0.0), expected(g * g, 0.0);
  const double cell = 1.0 / (g * g);
  for (int i = 0; i < g; ++i) {
    for (int j = 0; j < g; ++j) {
      const double area = i + j < g - 1 ? cell : (i + j == g - 1 ? 0.5 * cell : 0.0);
      expected[i * g + j] = n * area / 0.5;
    }
  }
  Rng rng(12);
  for (int k = 0; k < n; ++k) {
    const Vector3f b = SampleUniformTriangle(rng.NextFloat(), rng.NextFloat());
    ASSERT_GE(b.minCoeff(), 0.0f);
    ASSERT_NEAR(b.sum(), 1.0f, 1e-6f);
    observed[std::min(g - 1, int(b[0] * g)) * g + std::min(g - 1, int(b[1] * g))] += 1;
  }
  const test::ChiSquare chi = test::PearsonChiSquare(observed, expected);
  EXPECT_LT(chi.z, 4.0) << chi.statistic;
  EXPECT_EQ(chi.impossible, 0);
}

TEST(Sampling, PowerHeuristic) {
  EXPECT_FLOAT_EQ(PowerHeuristic(1, 1.0f, 1, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(PowerHeuristic(1, 3.0f, 1, 1.0f), 0.9f);
  EXPECT_FLOAT_EQ(PowerHeuristic(1, 3.0f, 1, 1.0f) + PowerHeuristic(1, 1.0f, 1, 3.0f), 1.0f);
  EXPECT_FLOAT_EQ(PowerHeuristic(2, 1.0f, 1, 2.0f), 0.5f);
  EXPECT_EQ(PowerHeuristic(1, 0.0f, 1, 0.0f), 0.0f);
  EXPECT_EQ(PowerHeuristic(1, 1e30f, 1, 1.0f), 1.0f);
  EXPECT_EQ(PowerHeuristic(1, 0.0f, 1, 1.0f), 0.0f);
}

// The visible-normal sampler against D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z,
// for isotropic and anisotropic widths and view angles from normal to 85 deg.
TEST(Sampling, GgxVisibleNormals) {
  struct Case {
    float ax, ay, theta_deg, phi_deg;
  };
  for (const Case c : {Case{0.3f, 0.3f, 0, 0}, Case{0.3f, 0.3f, 60, 30}, Case{0.8f, 0.8f, 85, 0},
                       Case{0.2f, 0.6f, 45, 70}, Case{1.0f, 1.0f, 30, 200}}) {
    SCOPED_TRACE(testing::Message() << c.ax << " " << c.ay << " " << c.theta_deg);
    const float th = c.theta_deg * kPi / 180, ph = c.phi_deg * kPi / 180;
    const Vector3f wo(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    // 30 z-bins: the density near the pole is peaked for alpha = 0.2.
    ExpectMatches(test::TestDirections(
                      [&](float a, float b) { return SampleGgxVisibleNormal(wo, c.ax, c.ay, a, b); },
                      [&](const Vector3f& m) { return GgxVisibleNormalPdf(wo, m, c.ax, c.ay); }, kSamples, 21, 30,
                      30, 8),
                  3e-3);
  }
}

// D is normalised: integral of D(m) m.z over the hemisphere = 1, and the Smith
// G1 is the normalisation of the visible normals: integral of max(0, wo.m) D(m)
// = wo.z / G1(wo). Checked by the midpoint rule in (z, phi) to 1e-3.
TEST(Sampling, GgxNormalisation) {
  for (float alpha : {0.1f, 0.5f, 1.0f}) {
    const Vector3f wo = Vector3f(0.6f, 0.1f, 0.5f).normalized();
    const int nz = 4000, np = 64;
    double proj = 0, vis = 0;
    for (int i = 0; i < nz; ++i) {
      for (int j = 0; j < np; ++j) {
        const double z = (i + 0.5) / nz, phi = 2 * M_PI * (j + 0.5) / np, s = std::sqrt(1 - z * z);
        const Vector3f m(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z));
        const double d = GgxD(m, alpha, alpha);
        proj += d * z;
        vis += d * std::max(0.0f, wo.dot(m));
      }
    }
    const double cell = (1.0 / nz) * (2 * M_PI / np);
    EXPECT_NEAR(proj * cell, 1.0, 1e-3) << alpha;
    EXPECT_NEAR(vis * cell, wo.z() / GgxG1(wo, alpha, alpha), 1e-3) << alpha;
  }
}

TEST(Sampling, GgxGrazingAndSmoothLimits) {
  // No NaN or inf at cos -> 0 or alpha at its floor; G terms within [0, 1].
  for (float alpha : {1e-3f, 0.5f, 1.0f}) {
    for (float cz : {0.0f, 1e-7f, 1e-3f, 1.0f}) {
      const Vector3f w(std::sqrt(1 - cz * cz), 0, cz);
      const float g1 = GgxG1(w, alpha, alpha);
      EXPECT_TRUE(std::isfinite(g1));
      EXPECT_GE(g1, 0.0f);
      EXPECT_LE(g1, 1.0f);
      const Vector3f m = SampleGgxVisibleNormal(w, alpha, alpha, 0.3f, 0.7f);
      EXPECT_TRUE(m.allFinite());
      EXPECT_NEAR(m.norm(), 1.0f, 1e-5f);
      EXPECT_TRUE(std::isfinite(GgxVisibility(w, w, alpha, alpha)));
      EXPECT_TRUE(std::isfinite(GgxReflectionPdf(w, m, alpha, alpha)));
    }
  }
  EXPECT_NEAR(GgxG1(Vector3f(0, 0, 1), 0.5f, 0.5f), 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(GgxD(Vector3f(0, 0, 1), 0.5f, 0.5f), 1.0f / (kPi * 0.25f));
}

}  // namespace
}  // namespace lt

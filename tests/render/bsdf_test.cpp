#include "render/bsdf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "render/microfacet.h"
#include "render/sampling.h"
#include "render/specular_albedo.h"

namespace lt {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

Vector3f Dir(float theta_deg, float phi_deg = 0) {
  const float t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

BsdfParams Params(Vector3f base, float metallic, float roughness) {
  BsdfParams p;
  p.base_color = base;
  p.metallic = metallic;
  p.roughness = roughness;
  return p;
}

// Mean and standard error of the sampling estimator of the albedo
// integral f cos dwi, from n x n stratified (u1, u2) with u3 from an Rng.
struct Estimate {
  Vector3d mean = Vector3d::Zero();
  Vector3d stderr_ = Vector3d::Zero();
  double valid_fraction = 0;
};

Estimate SampledAlbedo(const Bsdf& bsdf, const Vector3f& wo, int n, uint64_t seed) {
  Rng rng(seed);
  Vector3d sum = Vector3d::Zero(), sum2 = Vector3d::Zero();
  int valid = 0;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const float u1 = (a + rng.NextFloat()) / n, u2 = (b + rng.NextFloat()) / n;
      const BsdfSample s = bsdf.Sample(wo, u1, u2, rng.NextFloat());
      if (!s.valid()) continue;
      ++valid;
      const Vector3d w = s.weight.cast<double>();
      sum += w;
      sum2 += w.cwiseProduct(w);
    }
  }
  const double count = double(n) * n;
  Estimate e;
  e.mean = sum / count;
  // Standard error of an i.i.d. mean; stratification only lowers the true error.
  e.stderr_ = ((sum2 / count - e.mean.cwiseProduct(e.mean)) / count).cwiseMax(0.0).cwiseSqrt();
  e.valid_fraction = valid / count;
  return e;
}

// The table holds what the quadrature computes: recompute a spread of entries.
TEST(SpecularAlbedo, TableMatchesQuadrature) {
  for (int k = 0; k < 6; ++k) {
    const int i = (k * 37 + 5) % kSpecularAlbedoNodes, j = (k * 23 + 3) % kSpecularAlbedoNodes;
    const double e = GgxDirectionalAlbedo(SpecularAlbedoNodeMu(i), SpecularAlbedoNodeAlpha(j), kDielectricF0,
                                          kSpecularAlbedoQuadrature);
    // The table is printed with 7 significant digits.
    EXPECT_NEAR(DielectricSpecularAlbedoNode(i, j), e, 1e-6 * e + 1e-9) << i << " " << j;
  }
}

// Between the nodes the bilinear interpolant stays within 4e-3 of a 160 x 160
// quadrature (measured worst case over 300 random points 2.3e-3, at alpha near
// its floor and grazing view, cos_o ~ 1e-3; elsewhere far closer). Points off
// the nodes, crowded where E changes fastest.
TEST(SpecularAlbedo, InterpolationAccuracy) {
  const std::pair<float, float> points[] = {{1e-3f, 0.03f}, {2.2e-3f, 0.06f}, {0.011f, 0.1f}, {0.05f, 0.21f},
                                            {0.31f, 0.45f}, {0.72f, 0.81f},   {0.97f, 0.99f},  {0.5f, 0.05f}};
  for (auto [mu, roughness] : points) {
    const float alpha = std::max(roughness * roughness, kMinGgxAlpha);
    const double ref = GgxDirectionalAlbedo(mu, alpha, kDielectricF0, 160);
    EXPECT_NEAR(DielectricSpecularAlbedo(mu, alpha), ref, 4e-3) << "roughness " << roughness << " mu " << mu;
  }
}

// E_avg = 2 integral E mu dmu of the interpolated table (midpoint rule, 20000
// points: error below 1e-5).
TEST(SpecularAlbedo, AverageIsCosineWeightedIntegral) {
  for (float alpha : {kMinGgxAlpha, 0.01f, 0.2f, 0.5f, 1.0f}) {
    const int n = 20000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const float mu = (i + 0.5f) / n;
      sum += DielectricSpecularAlbedo(mu, alpha) * mu;
    }
    EXPECT_NEAR(DielectricSpecularAlbedoAverage(alpha), 2 * sum / n, 2e-5) << alpha;
  }
}

// A GgxAlpha holds the clamped alpha of a roughness and that alpha's table
// row; the default is the smoothest alpha, and a BSDF built from it evaluates
// to the same bits as one built from the roughness.
TEST(SpecularAlbedo, GgxAlphaLocatesItsRow) {
  const GgxAlpha smooth;
  EXPECT_EQ(smooth.alpha, kMinGgxAlpha);
  EXPECT_EQ(smooth.row.j, SpecularAlbedoRow(kMinGgxAlpha).j);
  EXPECT_EQ(smooth.row.f, SpecularAlbedoRow(kMinGgxAlpha).f);
  const Vector3f wo = Dir(60, 10), wi = Dir(30, 200);
  for (float roughness : {-0.5f, 0.0f, 0.02f, 0.3f, 0.77f, 1.0f, 2.0f}) {
    const GgxAlpha g(roughness);
    const float r = std::clamp(roughness, 0.0f, 1.0f);
    EXPECT_EQ(g.alpha, std::max(r * r, kMinGgxAlpha)) << roughness;
    EXPECT_EQ(DielectricSpecularAlbedo(0.4f, g.row), DielectricSpecularAlbedo(0.4f, g.alpha)) << roughness;
    EXPECT_EQ(DielectricSpecularAlbedoAverage(g.row), DielectricSpecularAlbedoAverage(g.alpha)) << roughness;
    const Vector3f base(0.8f, 0.5f, 0.2f);
    EXPECT_EQ(Bsdf(base, 0.3f, g).Evaluate(wo, wi), Bsdf(Params(base, 0.3f, roughness)).Evaluate(wo, wi));
  }
}

// White furnace: the sampled albedo never exceeds 1, and is exactly 1 (up to
// the table error) for a white dielectric base, whose Lambert lobe takes all
// the energy the specular lobe does not reflect. 64 x 64 stratified samples
// per case; bound = 1 + 5 standard errors (i.i.d. estimate, which overstates
// the error of stratified samples) + 4e-3 (table accuracy).
TEST(Bsdf, WhiteFurnace) {
  struct Material {
    Vector3f base;
    float metallic;
    bool white_dielectric;
  };
  const Material materials[] = {{Vector3f::Ones(), 0.0f, true},
                                {Vector3f::Ones(), 1.0f, false},
                                {Vector3f(0.9f, 0.5f, 0.1f), 0.5f, false}};
  for (const Material& m : materials) {
    for (float roughness : {0.0f, 0.1f, 0.4f, 1.0f}) {
      const Bsdf bsdf(Params(m.base, m.metallic, roughness));
      for (float theta : {0.0f, 60.0f, 85.0f, 89.5f}) {
        SCOPED_TRACE(testing::Message() << "metallic " << m.metallic << " roughness " << roughness << " theta "
                                        << theta);
        const Estimate e = SampledAlbedo(bsdf, Dir(theta, 20), 64, 100 + int(theta));
        for (int c = 0; c < 3; ++c) {
          const double bound = 5 * e.stderr_[c] + 4e-3;
          EXPECT_LE(e.mean[c], 1.0 + bound);
          EXPECT_GE(e.mean[c], 0.0);
          if (m.white_dielectric) {
            EXPECT_NEAR(e.mean[c], 1.0, bound);
          }
        }
      }
    }
  }
}

// A smooth metal is a Schlick mirror: albedo F(f0 = base, cos_o). The lobe is
// so narrow (alpha = 1e-3) that G2/G1 and F(wo.m) equal their values at m = n
// to 1e-3 up to 60 degrees.
TEST(Bsdf, SmoothMetalIsSchlickMirror) {
  const Vector3f base(0.95f, 0.64f, 0.54f);
  const Bsdf bsdf(Params(base, 1.0f, 0.0f));
  for (float theta : {0.0f, 30.0f, 60.0f}) {
    const Vector3f wo = Dir(theta, 45);
    const Estimate e = SampledAlbedo(bsdf, wo, 32, 3);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.mean[c], SchlickFresnel(base[c], wo.z()), 1e-3) << theta;
    const BsdfSample s = bsdf.Sample(wo, 0.3f, 0.6f, 0.5f);
    ASSERT_TRUE(s.valid());
    EXPECT_TRUE(s.specular);
    EXPECT_LT((s.wi - Vector3f(-wo.x(), -wo.y(), wo.z())).norm(), 5e-3f);  // mirror direction
  }
}

// The cancellation-free forms equal glTF appendix B's formulas, evaluated here
// in double from the specification's text: D = a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2),
// V = 0.5 / (n.l sqrt((n.v)^2 (1 - a^2) + a^2) + n.v sqrt((n.l)^2 (1 - a^2) + a^2)).
TEST(Bsdf, MatchesGltfSpecularFormula) {
  const Vector3f base(0.7f, 0.3f, 0.9f);
  for (float roughness : {0.2f, 0.5f, 1.0f}) {
    const Bsdf bsdf(Params(base, 1.0f, roughness));  // metal: no diffuse lobe
    const double a = double(roughness) * roughness, a2 = a * a;
    for (auto [to, po, ti, pi] :
         {std::tuple{10.f, 0.f, 20.f, 180.f}, {50.f, 30.f, 40.f, 250.f}, {80.f, 0.f, 5.f, 90.f}}) {
      const Vector3d v = Dir(to, po).cast<double>(), l = Dir(ti, pi).cast<double>();
      const Vector3d h = (v + l).normalized();
      const double nh = h.z(), nv = v.z(), nl = l.z(), vh = v.dot(h);
      const double d = a2 / (M_PI * std::pow(nh * nh * (a2 - 1) + 1, 2));
      const double vis = 0.5 / (nl * std::sqrt(nv * nv * (1 - a2) + a2) + nv * std::sqrt(nl * nl * (1 - a2) + a2));
      const Vector3f f = bsdf.Evaluate(Dir(to, po), Dir(ti, pi));
      for (int c = 0; c < 3; ++c) {
        const double fresnel = base[c] + (1 - base[c]) * std::pow(1 - vh, 5);
        EXPECT_NEAR(f[c], fresnel * d * vis, 1e-4 * fresnel * d * vis);
      }
    }
  }
}

TEST(Bsdf, Reciprocity) {
  Rng rng(5);
  for (int k = 0; k < 2000; ++k) {
    const Bsdf bsdf(Params(Vector3f(rng.NextFloat(), rng.NextFloat(), rng.NextFloat()), rng.NextFloat(),
                           rng.NextFloat()));
    const Vector3f wo = SampleUniformHemisphere(rng.NextFloat(), rng.NextFloat());
    const Vector3f wi = SampleUniformHemisphere(rng.NextFloat(), rng.NextFloat());
    const Vector3f a = bsdf.Evaluate(wo, wi), b = bsdf.Evaluate(wi, wo);
    // float rounding of the half vector and of the table lookups: 1e-5 relative.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-5f * std::max(a[c], 1e-6f));
  }
}

// Sample() reports the pdf and f that Pdf() and Evaluate() give for its wi,
// and weight = f cos / pdf. Sample() computes D from the sampled microfacet
// normal, Pdf() and Evaluate() from the half vector of wo and the float wi; the
// rounding of wi (a few 1e-7) turns the half vector by up to 2.4e-7 / (2 wo.h),
// and D changes by at most 2/alpha per radian, so the relative tolerance is
// 1e-4 + 1e-6 / (alpha wo.h) (four times that bound).
TEST(Bsdf, SamplePdfMatchesPdf) {
  Rng rng(9);
  int checked = 0;
  for (float roughness : {0.0f, 0.05f, 0.4f, 1.0f}) {
    for (float metallic : {0.0f, 0.5f, 1.0f}) {
      const Bsdf bsdf(Params(Vector3f(0.8f, 0.5f, 0.2f), metallic, roughness));
      for (int k = 0; k < 500; ++k) {
        const Vector3f wo = SampleUniformHemisphere(rng.NextFloat(), rng.NextFloat());
        const BsdfSample s = bsdf.Sample(wo, rng.NextFloat(), rng.NextFloat(), rng.NextFloat());
        if (!s.valid()) continue;
        ++checked;
        EXPECT_NEAR(s.wi.norm(), 1.0f, 1e-5f);
        const float tol = 1e-4f + 1e-6f / (bsdf.alpha() * wo.dot((wo + s.wi).normalized()));
        EXPECT_NEAR(s.pdf, bsdf.Pdf(wo, s.wi), tol * s.pdf);
        const Vector3f f = bsdf.Evaluate(wo, s.wi);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(s.f[c], f[c], tol * f[c] + 1e-7f);
          EXPECT_NEAR(s.weight[c], s.f[c] * s.wi.z() / s.pdf, 1e-5f * s.weight[c] + 1e-7f);
        }
      }
    }
  }
  EXPECT_GT(checked, 5000);
}

// The albedo by importance sampling equals the albedo by uniform sampling of
// the hemisphere (pdf 1/(2 pi)), and the pdf integrates to the fraction of
// valid samples (the specular lobe loses the reflections that fall below the
// horizon). Uniform sampling is only efficient for rough lobes; 50k uniform
// and 96 x 96 importance samples; tolerance 5 combined standard errors.
TEST(Bsdf, SampledAlbedoEqualsUniformIntegration) {
  for (float roughness : {0.3f, 1.0f}) {
    for (float theta : {0.0f, 70.0f}) {
      SCOPED_TRACE(testing::Message() << "roughness " << roughness << " theta " << theta);
      const Bsdf bsdf(Params(Vector3f(0.9f, 0.6f, 0.3f), 0.3f, roughness));
      const Vector3f wo = Dir(theta, 10);
      const Estimate sampled = SampledAlbedo(bsdf, wo, 96, 7);
      Rng rng(8);
      const int n = 50000;
      Vector3d sum = Vector3d::Zero(), sum2 = Vector3d::Zero();
      double pdf_sum = 0, pdf_sum2 = 0;
      for (int k = 0; k < n; ++k) {
        const Vector3f wi = SampleUniformHemisphere(rng.NextFloat(), rng.NextFloat());
        const Vector3d v = (bsdf.Evaluate(wo, wi) * wi.z() / UniformHemispherePdf()).cast<double>();
        sum += v;
        sum2 += v.cwiseProduct(v);
        const double p = bsdf.Pdf(wo, wi) / UniformHemispherePdf();
        pdf_sum += p;
        pdf_sum2 += p * p;
      }
      const Vector3d mean = sum / n;
      const Vector3d se = ((sum2 / n - mean.cwiseProduct(mean)) / n).cwiseSqrt();
      for (int c = 0; c < 3; ++c) {
        const double tol = 5 * std::hypot(se[c], sampled.stderr_[c]);
        EXPECT_NEAR(sampled.mean[c], mean[c], tol);
      }
      const double pdf_mean = pdf_sum / n, pdf_se = std::sqrt((pdf_sum2 / n - pdf_mean * pdf_mean) / n);
      // The valid fraction is a binomial proportion over 9216 draws.
      const double frac_se = std::sqrt(sampled.valid_fraction * (1 - sampled.valid_fraction) / 9216.0);
      EXPECT_NEAR(pdf_mean, sampled.valid_fraction, 5 * std::hypot(pdf_se, frac_se) + 1e-6);
      EXPECT_LE(pdf_mean, 1.0 + 5 * pdf_se);
    }
  }
}

// f >= 0 and finite, pdf finite, and samples finite, at grazing angles
// (cos -> 0) and at roughness 0 and 1.
TEST(Bsdf, FiniteAndNonNegativeAtExtremes) {
  const float cosines[] = {0.0f, 1e-7f, 1e-6f, 2e-6f, 1e-4f, 1e-2f, 0.5f, 1.0f};
  for (float roughness : {0.0f, 1e-4f, 0.5f, 1.0f}) {
    for (float metallic : {0.0f, 1.0f}) {
      const Bsdf bsdf(Params(Vector3f(1.0f, 0.5f, 0.0f), metallic, roughness));
      for (float co : cosines) {
        for (float ci : cosines) {
          for (float dphi : {0.0f, 90.0f, 180.0f}) {
            const float so = std::sqrt(1 - co * co), si = std::sqrt(1 - ci * ci);
            const float p = dphi * kPi / 180;
            const Vector3f wo(so, 0, co), wi(si * std::cos(p), si * std::sin(p), ci);
            const Vector3f f = bsdf.Evaluate(wo, wi);
            ASSERT_TRUE(f.allFinite()) << roughness << " " << co << " " << ci << " " << dphi;
            ASSERT_GE(f.minCoeff(), 0.0f);
            const float pdf = bsdf.Pdf(wo, wi);
            ASSERT_TRUE(std::isfinite(pdf));
            ASSERT_GE(pdf, 0.0f);
            if (co < Bsdf::kMinCos || ci < Bsdf::kMinCos) {
              ASSERT_EQ(f, Vector3f::Zero());
            }
          }
          const Vector3f wo(std::sqrt(1 - co * co), 0, co);
          for (float u3 : {0.05f, 0.95f}) {
            const BsdfSample s = bsdf.Sample(wo, 0.999f, 0.25f, u3);
            ASSERT_TRUE(s.weight.allFinite());
            ASSERT_TRUE(s.f.allFinite());
            ASSERT_TRUE(std::isfinite(s.pdf));
            if (s.valid()) {
              ASSERT_GE(s.wi.z(), Bsdf::kMinCos);
              ASSERT_GE(s.weight.minCoeff(), 0.0f);
            } else {
              ASSERT_EQ(s.weight, Vector3f::Zero());
            }
          }
        }
      }
    }
  }
  // wo = wi = n: the half vector is n, D at its peak.
  const Bsdf smooth(Params(Vector3f::Ones(), 0.0f, 0.0f));
  EXPECT_TRUE(smooth.Evaluate(Vector3f(0, 0, 1), Vector3f(0, 0, 1)).allFinite());
}

TEST(Bsdf, SpecularProbabilityFollowsAlbedos) {
  // Pure metal: only the specular lobe. Dielectric: bounded, rising to grazing.
  EXPECT_EQ(Bsdf(Params(Vector3f::Ones(), 1.0f, 0.5f)).SpecularProbability(0.5f), 1.0f);
  const Bsdf dielectric(Params(Vector3f::Ones(), 0.0f, 0.5f));
  EXPECT_EQ(dielectric.SpecularProbability(1.0f), Bsdf::kMinSpecularProbability);
  EXPECT_GT(dielectric.SpecularProbability(0.05f), dielectric.SpecularProbability(0.5f));
  EXPECT_LE(dielectric.SpecularProbability(0.0f), Bsdf::kMaxSpecularProbability);
  // Black dielectric: no diffuse energy, all samples specular.
  EXPECT_EQ(Bsdf(Params(Vector3f::Zero(), 0.0f, 0.5f)).SpecularProbability(0.5f), 1.0f);
}

TEST(Bsdf, ParamsCheck) {
  EXPECT_NO_THROW(Params(Vector3f(0.5f, 0.5f, 0.5f), 0.0f, 1.0f).Check("m.json: /materials/0"));
  try {
    Params(Vector3f(0.5f, 1.5f, 0.5f), 0.0f, 1.0f).Check("m.json: /materials/0");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "m.json: /materials/0: base_color[1] must be in [0, 1], got 1.5");
  }
  EXPECT_THROW(Params(Vector3f::Ones(), NAN, 1.0f).Check("x"), InputError);
  EXPECT_THROW(Params(Vector3f::Ones(), 0.0f, -0.1f).Check("x"), InputError);
}

}  // namespace
}  // namespace lt

#include "render/bsdf.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "render/microfacet.h"
#include "render/sampling.h"
#include "render/specular_albedo.h"

namespace lt {
namespace {

float Clamp01(float v) { return std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f); }

void CheckUnit(const std::string& where, const std::string& name, float v) {
  if (!(v >= 0.0f && v <= 1.0f)) {
    throw InputError(where, name + " must be in [0, 1], got " + FormatNumber(v));
  }
}

}  // namespace

void BsdfParams::Check(const std::string& where) const {
  for (int c = 0; c < 3; ++c) CheckUnit(where, "base_color[" + std::to_string(c) + "]", base_color[c]);
  CheckUnit(where, "metallic", metallic);
  CheckUnit(where, "roughness", roughness);
}

GgxAlpha::GgxAlpha(float roughness) {
  const float r = Clamp01(roughness);
  alpha = std::max(r * r, kMinGgxAlpha);
  row = SpecularAlbedoRow(alpha);
}

Bsdf::Bsdf(const BsdfParams& p) : Bsdf(p.base_color, p.metallic, GgxAlpha(p.roughness)) {}

Bsdf::Bsdf(const Eigen::Vector3f& base_color, float metallic_factor, const GgxAlpha& alpha) : ggx_(alpha) {
  const Eigen::Vector3f base(Clamp01(base_color.x()), Clamp01(base_color.y()), Clamp01(base_color.z()));
  const float metallic = Clamp01(metallic_factor);
  f0_ = (1.0f - metallic) * Eigen::Vector3f::Constant(kDielectricF0) + metallic * base;
  const Eigen::Vector3f c_diff = (1.0f - metallic) * base;
  // 1 - E_avg >= 1 - (largest dielectric albedo) > 0.9: no division hazard.
  diffuse_ = c_diff * (kInvPi / (1.0f - DielectricSpecularAlbedoAverage(ggx_.row)));
  diffuse_weight_ = c_diff.mean();
}

float Bsdf::SpecularProbability(float cos_o) const {
  if (diffuse_weight_ <= 0.0f) return 1.0f;
  return SpecularProbabilityWithAlbedo(cos_o, DielectricSpecularAlbedo(cos_o, ggx_.row));
}

// E reads its cosine clamped to [0, 1], so e_o = E(cos_o) whether or not cos_o was clamped.
float Bsdf::SpecularProbabilityWithAlbedo(float cos_o, float e_o) const {
  const float mu = std::clamp(cos_o, 0.0f, 1.0f);
  if (diffuse_weight_ <= 0.0f) return 1.0f;
  const float spec = (SchlickFresnel(f0_.x(), mu) + SchlickFresnel(f0_.y(), mu) + SchlickFresnel(f0_.z(), mu)) / 3;
  const float diff = diffuse_weight_ * (1.0f - e_o);
  return std::clamp(spec / (spec + diff), kMinSpecularProbability, kMaxSpecularProbability);
}

Eigen::Vector3f Bsdf::EvaluateWithHalf(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, const Eigen::Vector3f& h,
                                       float e_o) const {
  const float wo_h = std::clamp(wo.dot(h), 0.0f, 1.0f);
  const float m = 1.0f - wo_h, m2 = m * m, m5 = m2 * m2 * m;
  const Eigen::Vector3f fresnel = f0_ + (Eigen::Vector3f::Ones() - f0_) * m5;
  const float dv = GgxD(h, ggx_.alpha, ggx_.alpha) * GgxVisibility(wo, wi, ggx_.alpha, ggx_.alpha);
  const float coupling = (1.0f - e_o) * (1.0f - DielectricSpecularAlbedo(wi.z(), ggx_.row));
  return fresnel * dv + diffuse_ * coupling;
}

float Bsdf::PdfWithHalf(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, const Eigen::Vector3f& h,
                        float ps) const {
  return ps * GgxReflectionPdf(wo, h, ggx_.alpha, ggx_.alpha) + (1.0f - ps) * CosineHemispherePdf(wi.z());
}

Eigen::Vector3f Bsdf::Evaluate(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi) const {
  if (wo.z() < kMinCos || wi.z() < kMinCos) return Eigen::Vector3f::Zero();
  return EvaluateWithHalf(wo, wi, (wo + wi).normalized(), DielectricSpecularAlbedo(wo.z(), ggx_.row));
}

float Bsdf::Pdf(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi) const {
  if (wo.z() < kMinCos || wi.z() < kMinCos) return 0.0f;
  return PdfWithHalf(wo, wi, (wo + wi).normalized(), SpecularProbability(wo.z()));
}

BsdfSample Bsdf::Sample(const Eigen::Vector3f& wo, float u1, float u2, float u3) const {
  BsdfSample s;
  if (wo.z() < kMinCos) return s;
  // E(cos_o) once, for the lobe choice, the pdf and f.
  const float e_o = DielectricSpecularAlbedo(wo.z(), ggx_.row);
  const float ps = SpecularProbabilityWithAlbedo(wo.z(), e_o);
  Eigen::Vector3f wi, h;
  if (u3 < ps) {
    h = SampleGgxVisibleNormal(wo, ggx_.alpha, ggx_.alpha, u1, u2);
    wi = 2.0f * wo.dot(h) * h - wo;
    if (wi.z() < kMinCos) return s;
    wi.normalize();  // remove the rounding of the reflection
    s.specular = true;
  } else {
    wi = SampleCosineHemisphere(u1, u2);
    if (wi.z() < kMinCos) return s;
    h = (wo + wi).normalized();
  }
  const float pdf = PdfWithHalf(wo, wi, h, ps);
  if (!(pdf > 0.0f) || !std::isfinite(pdf)) return s;
  s.wi = wi;
  s.f = EvaluateWithHalf(wo, wi, h, e_o);
  s.pdf = pdf;
  s.weight = s.f * (wi.z() / pdf);
  return s;
}

}  // namespace lt

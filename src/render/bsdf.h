// The glTF 2.0 metallic-roughness BSDF (glTF 2.0 specification, appendix B):
//
//   f = (1 - metallic) * f_diffuse + f_specular
//   f_specular = F(wo.h) D(h) G2(wo, wi) / (4 cos_o cos_i)      GGX, height-correlated Smith
//   F = Schlick with F0 = mix(0.04, base_color, metallic)       (= mix of the dielectric
//                                                                 and metal Fresnel terms)
//   f_diffuse = base_color / pi * (1 - E(cos_o)) (1 - E(cos_i)) / (1 - E_avg)
//
// where E is the directional albedo of the dielectric specular lobe
// (render/specular_albedo.h). This albedo-scaled coupling of the Lambert base
// to the specular layer (Kelemen & Szirmay-Kalos 2001; Kulla & Conty 2017) is
// reciprocal and energy conserving: the dielectric albedo is E + c (1 - E) <= 1,
// exactly 1 for a white base. glTF's own fresnel_mix, which weights the diffuse
// lobe by 1 - F(wo.h), reflects more than it receives at grazing angles
// (docs/rendering.md, "BSDF").
//
// Directions are unit vectors in the local shading frame (z = shading normal),
// both pointing away from the surface. The BSDF is one-sided: f = 0 unless
// cos_o and cos_i >= kMinCos; the caller flips the frame for back faces of
// double-sided materials.
#pragma once

#include <Eigen/Core>
#include <string>

#include "render/specular_albedo.h"

namespace lt {

struct BsdfParams {
  // glTF defaults (baseColorFactor, metallicFactor, roughnessFactor).
  Eigen::Vector3f base_color = Eigen::Vector3f::Ones();  // linear RGB in [0, 1]
  float metallic = 1.0f;                                 // [0, 1]
  float roughness = 1.0f;                                // [0, 1]; alpha = roughness^2

  // Throws lt::InputError(where, ...) for values outside their ranges or NaN.
  void Check(const std::string& where) const;
};

struct BsdfSample {
  Eigen::Vector3f wi = Eigen::Vector3f::Zero();
  Eigen::Vector3f f = Eigen::Vector3f::Zero();       // f(wo, wi) [1/sr]
  Eigen::Vector3f weight = Eigen::Vector3f::Zero();  // f cos_i / pdf
  float pdf = 0.0f;       // density of wi over both lobes [1/sr]; 0 = no sample
  bool specular = false;  // drawn from the specular lobe
  bool valid() const { return pdf > 0.0f; }
};

// A surface's GGX alpha, roughness^2 clamped to [kMinGgxAlpha, 1] (a roughness
// outside [0, 1] is clamped first), with its row in the specular albedo table:
// made once per path vertex and shared by the BSDFs built there. The default
// is the smoothest alpha.
struct GgxAlpha {
  GgxAlpha() = default;
  explicit GgxAlpha(float roughness);
  float alpha = kMinGgxAlpha;
  SpecularAlbedoRow row;  // of alpha
};

class Bsdf {
 public:
  // Cosines below this count as below the horizon: f = 0, no sample.
  static constexpr float kMinCos = 1e-6f;
  // Bounds of the probability of sampling the specular lobe when both lobes
  // are present, so that neither is starved.
  static constexpr float kMinSpecularProbability = 0.1f;
  static constexpr float kMaxSpecularProbability = 0.9f;

  // Parameters outside their ranges are clamped (textures can push factors
  // out); roughness is clamped to alpha >= kMinGgxAlpha (render/specular_albedo.h).
  explicit Bsdf(const BsdfParams& params);
  // The same with the roughness given as its GgxAlpha.
  Bsdf(const Eigen::Vector3f& base_color, float metallic, const GgxAlpha& alpha);

  Eigen::Vector3f Evaluate(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi) const;

  // Draws wi: u3 picks the specular lobe (VNDF sampling, Heitz 2018) with
  // probability SpecularProbability(wo.z), else the cosine-weighted diffuse lobe;
  // u1, u2 place the direction. pdf is the one-sample MIS mixture
  //   p = P_spec p_spec(wi) + (1 - P_spec) p_diffuse(wi),
  // so weight = f cos_i / p is the balance-heuristic estimator. Invalid (pdf 0)
  // when wo or the drawn wi is below the horizon.
  BsdfSample Sample(const Eigen::Vector3f& wo, float u1, float u2, float u3) const;

  float Pdf(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi) const;

  // Probability of choosing the specular lobe, from the estimated albedos of
  // the two lobes at cos_o.
  float SpecularProbability(float cos_o) const;

  float alpha() const { return ggx_.alpha; }

 private:
  // e_o: the dielectric specular albedo E(wo.z); ps: SpecularProbability(wo.z)
  // (Sample computes each once).
  float SpecularProbabilityWithAlbedo(float cos_o, float e_o) const;
  Eigen::Vector3f EvaluateWithHalf(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, const Eigen::Vector3f& h,
                                   float e_o) const;
  float PdfWithHalf(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, const Eigen::Vector3f& h, float ps) const;

  Eigen::Vector3f diffuse_;  // (1 - metallic) base_color / (pi (1 - E_avg))
  Eigen::Vector3f f0_;       // mix(0.04, base_color, metallic)
  GgxAlpha ggx_;
  float diffuse_weight_;  // mean of (1 - metallic) base_color, for the lobe choice
};

}  // namespace lt

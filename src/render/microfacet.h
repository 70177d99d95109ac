// GGX (Trowbridge–Reitz) microfacet distribution: normal distribution D,
// Smith masking G1 and height-correlated masking-shadowing G2, and sampling of
// the distribution of visible normals (Heitz 2018). Directions are in the local
// shading frame (z = macro-normal). alpha_x, alpha_y are the roughness widths
// along x and y (isotropic: equal). Formulas: docs/rendering.md, "Microfacet".
//
// The forms below avoid cancellation: 1 + (alpha^2 - 1) cos^2 is written as
// sin^2 + alpha^2 cos^2 with sin^2 = x^2 + y^2, and G1, G2 are written without
// dividing by cos(theta), so they stay finite at grazing angles.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace lt {

// D(m): density of microfacet normals per unit projected area, so that
// integral of D(m) m.z dm over the hemisphere = 1. Zero for m.z <= 0.
inline float GgxD(const Eigen::Vector3f& m, float alpha_x, float alpha_y);

// Smith masking G1(w) = 1 / (1 + Lambda(w)) for the GGX distribution.
float GgxG1(const Eigen::Vector3f& w, float alpha_x, float alpha_y);

// Height-correlated masking-shadowing G2 = 1 / (1 + Lambda(wo) + Lambda(wi))
// (Heitz 2014, "Understanding the Masking-Shadowing Function").
float GgxG2(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, float alpha_x, float alpha_y);

// G2 / (4 |wo.z| |wi.z|): the "visibility" term of the specular BRDF, in a form
// without the division (finite as cosines go to 0 unless both are 0).
inline float GgxVisibility(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, float alpha_x, float alpha_y);

// A microfacet normal m drawn from the distribution of normals visible from wo
// (wo.z > 0): D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z (Heitz 2018, "Sampling
// the GGX Distribution of Visible Normals", JCGT 7(4)).
Eigen::Vector3f SampleGgxVisibleNormal(const Eigen::Vector3f& wo, float alpha_x, float alpha_y, float u1,
                                       float u2);
// D_wo(m), per steradian of m.
float GgxVisibleNormalPdf(const Eigen::Vector3f& wo, const Eigen::Vector3f& m, float alpha_x, float alpha_y);

// Density of the mirror direction wi = reflect(wo, m) when m ~ D_wo:
// D_wo(m) / (4 wo.m) = G1(wo) D(m) / (4 wo.z), with m the half vector of wo, wi.
inline float GgxReflectionPdf(const Eigen::Vector3f& wo, const Eigen::Vector3f& m, float alpha_x, float alpha_y);

// Directional albedo of the isotropic GGX specular lobe with Schlick Fresnel of
// normal reflectance f0, seen from cos(theta_o) = cos_theta:
//   E = integral of F(wo.h) D(h) G2 / (4 cos_o cos_i) cos_i dwi
//     = E_{m ~ D_wo}[F(wo.m) G2(wo, wi) / G1(wo)],  wi = reflect(wo, m),
// by deterministic stratified quadrature with n x n visible normals (midpoints).
double GgxDirectionalAlbedo(float cos_theta, float alpha, float f0, int n);

// D, the visibility term and the reflection pdf are defined here, inline: the
// BSDF evaluates them at every path vertex and connection.

// sqrt(w.z^2 + alpha_x^2 w.x^2 + alpha_y^2 w.y^2) = w.z sqrt(1 + tan^2 alpha^2),
// so that Lambda(w) = (S - w.z) / (2 w.z).
inline float GgxSmithS(const Eigen::Vector3f& w, float ax, float ay) {
  const float x = ax * w.x(), y = ay * w.y();
  return std::sqrt(w.z() * w.z() + x * x + y * y);
}

inline float GgxD(const Eigen::Vector3f& m, float ax, float ay) {
  if (m.z() <= 0.0f) return 0.0f;
  const float x = m.x() / ax, y = m.y() / ay;
  const float q = x * x + y * y + m.z() * m.z();
  return 1.0f / (3.14159265358979323846f * ax * ay * q * q);
}

inline float GgxVisibility(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, float ax, float ay) {
  if (wo.z() <= 0.0f || wi.z() <= 0.0f) return 0.0f;
  return 0.5f / (wi.z() * GgxSmithS(wo, ax, ay) + wo.z() * GgxSmithS(wi, ax, ay));
}

inline float GgxReflectionPdf(const Eigen::Vector3f& wo, const Eigen::Vector3f& m, float ax, float ay) {
  if (wo.z() <= 0.0f || wo.dot(m) <= 0.0f) return 0.0f;
  return GgxD(m, ax, ay) / (2.0f * (wo.z() + GgxSmithS(wo, ax, ay)));
}

}  // namespace lt

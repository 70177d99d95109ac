// Directional albedo of the dielectric GGX specular lobe of the glTF
// metallic-roughness BSDF (Schlick Fresnel with F0 = 0.04, height-correlated
// Smith), used to couple the diffuse lobe to the specular one so that the BSDF
// conserves energy (docs/rendering.md, "BSDF: energy conservation").
//
//   E(mu, alpha) = integral over the hemisphere of f_spec(wo, wi) cos(theta_i) dwi
//   E_avg(alpha) = 2 integral_0^1 E(mu, alpha) mu dmu
//
// E is tabulated (specular_albedo_table.inc, generated offline by
// tools/render/gen_specular_albedo_table.cpp) on 64 x 64 nodes
//   mu = t^4,  t = i / 63;   alpha = (r_min + (1 - r_min) s^1.5)^2,  s = j / 63,
// with r_min = sqrt(kMinGgxAlpha) (alpha is the square of glTF's roughness),
// which crowd the nodes where E changes fastest (grazing view of smooth
// surfaces), and read back by bilinear interpolation in (t, s). E_avg is the
// exact cosine-weighted integral of that interpolant, so the coupled diffuse
// lobe integrates exactly to 1 - E(mu) of the table.
#pragma once

#include <cmath>

namespace lt {

inline constexpr float kDielectricF0 = 0.04f;
// Smallest GGX alpha the renderer uses: roughness -> 0 is clamped here so that
// D, its sampling and the pdf stay finite in float (D(n) = 1/(pi alpha^2) = 3e5).
inline constexpr float kMinGgxAlpha = 1e-3f;

// Table layout (shared with the generator).
inline constexpr int kSpecularAlbedoNodes = 64;
inline constexpr int kSpecularAlbedoQuadrature = 128;  // n x n visible normals per entry
float SpecularAlbedoNodeMu(int i);     // mu of column i (the mu = 0 column holds the limit mu -> 0)
float SpecularAlbedoNodeAlpha(int j);  // alpha of row j

// Schlick's Fresnel approximation for reflectance f0 at normal incidence.
inline float SchlickFresnel(float f0, float cos_theta) {
  const float c = cos_theta < 0.0f ? 0.0f : (cos_theta > 1.0f ? 1.0f : cos_theta);
  const float m = 1.0f - c, m2 = m * m;
  return f0 + (1.0f - f0) * m2 * m2 * m;
}

// The place of one alpha between the table's rows: row j and the fraction f
// toward row j + 1. Locating an alpha costs a cube root, so a BSDF or a path
// vertex locates its alpha once and reads the table with it at every cosine.
// The default is the row of kMinGgxAlpha.
struct SpecularAlbedoRow {
  SpecularAlbedoRow() = default;
  explicit SpecularAlbedoRow(float alpha);
  int j = 0;
  float f = 0.0f;
};

// The table, row j (alpha) after row j - 1, column i (mu) within a row.
extern const float kSpecularAlbedoTable[kSpecularAlbedoNodes * kSpecularAlbedoNodes];

// The tabulated E(mu, alpha), mu = cos(theta_o) in [0, 1], alpha in [kMinGgxAlpha, 1]
// (inline: every BSDF evaluation reads it twice).
inline float DielectricSpecularAlbedo(float cos_theta, const SpecularAlbedoRow& alpha) {
  constexpr int kN = kSpecularAlbedoNodes;
  // Table coordinate t = mu^(1/4) in [0, 1], its column i and the fraction fi toward i + 1.
  const float mu = cos_theta < 0.0f ? 0.0f : (cos_theta > 1.0f ? 1.0f : cos_theta);
  const float t = std::sqrt(std::sqrt(mu));
  const float x = (t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t)) * float(kN - 1);
  const int i = int(x) < kN - 2 ? int(x) : kN - 2;
  const float fi = x - float(i);
  const float* r0 = kSpecularAlbedoTable + alpha.j * kN;
  const float* r1 = r0 + kN;
  const float e0 = r0[i] + fi * (r0[i + 1] - r0[i]);
  const float e1 = r1[i] + fi * (r1[i + 1] - r1[i]);
  return e0 + alpha.f * (e1 - e0);
}
float DielectricSpecularAlbedo(float cos_theta, float alpha);
// E_avg(alpha) of the interpolated table.
float DielectricSpecularAlbedoAverage(const SpecularAlbedoRow& alpha);
float DielectricSpecularAlbedoAverage(float alpha);
// The raw table entry at column i, row j.
float DielectricSpecularAlbedoNode(int i, int j);

}  // namespace lt

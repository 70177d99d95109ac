// Sampling utilities for the path tracer: orthonormal bases, warps from the
// unit square to directions and points with their densities, and the power
// heuristic for multiple importance sampling. Everything is float (render math);
// directions are unit vectors in a local frame whose z axis is the normal.
// Formulas and sources: docs/rendering.md, "Sampling".
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lt {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kTwoPi = 6.28318530717958647692f;
inline constexpr float kInvTwoPi = 0.15915494309189533577f;
inline constexpr float kInvFourPi = 0.07957747154594766788f;

// Right-handed orthonormal basis (b1, b2, n) from a unit normal n, without
// branches on n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void OrthonormalBasis(const Eigen::Vector3f& n, Eigen::Vector3f* b1, Eigen::Vector3f* b2);

// A shading frame: local (x, y, z) = (t, b, n).
struct Frame {
  Eigen::Vector3f t, b, n;

  static Frame FromNormal(const Eigen::Vector3f& n);
  Eigen::Vector3f ToLocal(const Eigen::Vector3f& w) const { return {t.dot(w), b.dot(w), n.dot(w)}; }
  Eigen::Vector3f ToWorld(const Eigen::Vector3f& v) const { return t * v.x() + b * v.y() + n * v.z(); }
};

// Unit disk, uniform by area (Shirley & Chiu 1997 concentric map). pdf = 1/pi.
Eigen::Vector2f SampleConcentricDisk(float u1, float u2);

// Hemisphere z >= 0, density proportional to cos(theta) (Malley's method on the
// concentric disk). pdf = cos(theta)/pi per steradian.
Eigen::Vector3f SampleCosineHemisphere(float u1, float u2);
inline float CosineHemispherePdf(float cos_theta) { return cos_theta > 0.0f ? cos_theta * kInvPi : 0.0f; }

// Hemisphere z >= 0, uniform. pdf = 1/(2 pi).
Eigen::Vector3f SampleUniformHemisphere(float u1, float u2);
inline float UniformHemispherePdf() { return kInvTwoPi; }

// Whole sphere, uniform. pdf = 1/(4 pi).
Eigen::Vector3f SampleUniformSphere(float u1, float u2);
inline float UniformSpherePdf() { return kInvFourPi; }

// Cone around +z of half-angle theta_max (cos_theta_max in [-1, 1]), uniform.
// pdf = 1/(2 pi (1 - cos_theta_max)) inside the cone.
Eigen::Vector3f SampleUniformCone(float u1, float u2, float cos_theta_max);
float UniformConePdf(float cos_theta_max);

// Triangle, uniform by area: barycentric coordinates (b0, b1, b2), b0+b1+b2 = 1.
// The point is b0*p0 + b1*p1 + b2*p2; pdf = 1/area.
Eigen::Vector3f SampleUniformTriangle(float u1, float u2);

// Veach's power heuristic (beta = 2): weight of a sample from strategy f, with
// nf samples of density f_pdf, against ng samples of strategy g of density g_pdf.
float PowerHeuristic(int nf, float f_pdf, int ng, float g_pdf);

}  // namespace lt

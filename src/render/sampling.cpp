#include "render/sampling.h"

#include <algorithm>
#include <cmath>

namespace lt {

void OrthonormalBasis(const Eigen::Vector3f& n, Eigen::Vector3f* b1, Eigen::Vector3f* b2) {
  const float sign = std::copysign(1.0f, n.z());
  const float a = -1.0f / (sign + n.z());
  const float b = n.x() * n.y() * a;
  *b1 = Eigen::Vector3f(1.0f + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  *b2 = Eigen::Vector3f(b, sign + n.y() * n.y() * a, -n.y());
}

Frame Frame::FromNormal(const Eigen::Vector3f& n) {
  Frame f;
  f.n = n;
  OrthonormalBasis(n, &f.t, &f.b);
  return f;
}

Eigen::Vector2f SampleConcentricDisk(float u1, float u2) {
  const float x = 2.0f * u1 - 1.0f, y = 2.0f * u2 - 1.0f;
  if (x == 0.0f && y == 0.0f) return {0.0f, 0.0f};
  float r, theta;
  if (std::abs(x) > std::abs(y)) {
    r = x;
    theta = 0.25f * kPi * (y / x);
  } else {
    r = y;
    theta = 0.5f * kPi - 0.25f * kPi * (x / y);
  }
  return {r * std::cos(theta), r * std::sin(theta)};
}

Eigen::Vector3f SampleCosineHemisphere(float u1, float u2) {
  const Eigen::Vector2f d = SampleConcentricDisk(u1, u2);
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.squaredNorm()));
  return {d.x(), d.y(), z};
}

Eigen::Vector3f SampleUniformHemisphere(float u1, float u2) {
  const float z = u1;
  const float r = std::sqrt(std::max(0.0f, (1.0f - z) * (1.0f + z)));
  const float phi = kTwoPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Eigen::Vector3f SampleUniformSphere(float u1, float u2) {
  const float z = 1.0f - 2.0f * u1;
  const float r = std::sqrt(std::max(0.0f, (1.0f - z) * (1.0f + z)));
  const float phi = kTwoPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Eigen::Vector3f SampleUniformCone(float u1, float u2, float cos_theta_max) {
  // 1 - cos(theta) is uniform in [0, 1 - cos_theta_max]; sin^2 = d (2 - d)
  // keeps precision for narrow cones where cos(theta) rounds to 1.
  const float d = u1 * (1.0f - cos_theta_max);
  const float z = 1.0f - d;
  const float r = std::sqrt(std::max(0.0f, d * (2.0f - d)));
  const float phi = kTwoPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

float UniformConePdf(float cos_theta_max) {
  const float solid_angle = kTwoPi * (1.0f - cos_theta_max);
  return solid_angle > 0.0f ? 1.0f / solid_angle : 0.0f;
}

Eigen::Vector3f SampleUniformTriangle(float u1, float u2) {
  const float su = std::sqrt(u1);
  const float b0 = 1.0f - su;
  const float b1 = u2 * su;
  return {b0, b1, std::max(0.0f, 1.0f - b0 - b1)};
}

float PowerHeuristic(int nf, float f_pdf, int ng, float g_pdf) {
  const float f = float(nf) * f_pdf, g = float(ng) * g_pdf;
  if (std::isinf(f * f)) return 1.0f;  // f dominates beyond float range
  const float denom = f * f + g * g;
  return denom > 0.0f ? f * f / denom : 0.0f;
}

}  // namespace lt

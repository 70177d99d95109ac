#include "render/microfacet.h"

#include <algorithm>
#include <cmath>

#include "render/sampling.h"

namespace lt {
float GgxG1(const Eigen::Vector3f& w, float ax, float ay) {
  if (w.z() <= 0.0f) return 0.0f;
  return 2.0f * w.z() / (w.z() + GgxSmithS(w, ax, ay));
}

float GgxG2(const Eigen::Vector3f& wo, const Eigen::Vector3f& wi, float ax, float ay) {
  if (wo.z() <= 0.0f || wi.z() <= 0.0f) return 0.0f;
  return 2.0f * wo.z() * wi.z() / (wi.z() * GgxSmithS(wo, ax, ay) + wo.z() * GgxSmithS(wi, ax, ay));
}

Eigen::Vector3f SampleGgxVisibleNormal(const Eigen::Vector3f& wo, float ax, float ay, float u1, float u2) {
  // Section 3 of Heitz 2018: stretch to the hemisphere configuration, sample the
  // projected area of the half disk seen from vh, unstretch.
  const Eigen::Vector3f vh = Eigen::Vector3f(ax * wo.x(), ay * wo.y(), wo.z()).normalized();
  const float lensq = vh.x() * vh.x() + vh.y() * vh.y();
  const Eigen::Vector3f t1 =
      lensq > 0.0f ? Eigen::Vector3f(-vh.y(), vh.x(), 0.0f) / std::sqrt(lensq) : Eigen::Vector3f(1.0f, 0.0f, 0.0f);
  const Eigen::Vector3f t2 = vh.cross(t1);
  const float r = std::sqrt(u1);
  const float phi = kTwoPi * u2;
  const float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  const float s = 0.5f * (1.0f + vh.z());
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  const Eigen::Vector3f nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return Eigen::Vector3f(ax * nh.x(), ay * nh.y(), std::max(0.0f, nh.z())).normalized();
}

float GgxVisibleNormalPdf(const Eigen::Vector3f& wo, const Eigen::Vector3f& m, float ax, float ay) {
  if (wo.z() <= 0.0f) return 0.0f;
  const float wo_m = wo.dot(m);
  if (wo_m <= 0.0f) return 0.0f;
  return 2.0f * wo_m * GgxD(m, ax, ay) / (wo.z() + GgxSmithS(wo, ax, ay));
}

double GgxDirectionalAlbedo(float cos_theta, float alpha, float f0, int n) {
  const float mu = std::clamp(cos_theta, 0.0f, 1.0f);
  const Eigen::Vector3f wo(std::sqrt(std::max(0.0f, (1.0f - mu) * (1.0f + mu))), 0.0f, mu);
  if (wo.z() <= 0.0f) return 0.0;
  const float g1 = GgxG1(wo, alpha, alpha);
  double sum = 0;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const Eigen::Vector3f m =
          SampleGgxVisibleNormal(wo, alpha, alpha, (float(a) + 0.5f) / float(n), (float(b) + 0.5f) / float(n));
      const float wo_m = wo.dot(m);
      const Eigen::Vector3f wi = 2.0f * wo_m * m - wo;
      if (wi.z() <= 0.0f) continue;
      const float c = 1.0f - std::clamp(wo_m, 0.0f, 1.0f), c2 = c * c;
      const float fresnel = f0 + (1.0f - f0) * c2 * c2 * c;
      sum += double(fresnel) * GgxG2(wo, wi, alpha, alpha) / g1;
    }
  }
  return sum / (double(n) * n);
}

}  // namespace lt

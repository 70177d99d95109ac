// Node positions of the specular albedo table (shared by the renderer and the
// offline table generator, so kept apart from the table itself).
#include <algorithm>
#include <cmath>

#include "render/specular_albedo.h"

namespace lt {

float SpecularAlbedoNodeMu(int i) {
  const double t = double(i) / (kSpecularAlbedoNodes - 1);
  return std::max(float(t * t * t * t), 1e-9f);
}

float SpecularAlbedoNodeAlpha(int j) {
  const double s = double(j) / (kSpecularAlbedoNodes - 1);
  const double r_min = std::sqrt(double(kMinGgxAlpha));
  const double r = r_min + (1.0 - r_min) * s * std::sqrt(s);
  return float(r * r);
}

}  // namespace lt

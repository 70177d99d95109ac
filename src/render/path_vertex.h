// The shading point of a path vertex, shared by the path tracer's source files.
#pragma once

#include <array>

#include "render/bsdf.h"
#include "render/path_tracer.h"
#include "render/sampling.h"

namespace lt {

struct PathTracer::Vertex {
  Eigen::Vector3d p;        // world
  Eigen::Vector3d n_geo;    // unit, on the side the path arrived from
  Eigen::Vector3d n_shade;  // unit, same side as n_geo
  Frame frame;              // shading frame (float)
  Eigen::Vector3f wo;       // local, toward where the path came from
  const Material* material = nullptr;
  uint32_t material_id = 0;
  Eigen::Vector3f base_color;
  GgxAlpha ggx;  // the material's GGX alpha
  std::array<float, kMaxGroups> albedo_mono{};  // base colour at each emitter's wavelength
  bool subsurface = false;

  Eigen::Vector3f ToLocal(const Eigen::Vector3d& w) const { return frame.ToLocal(w.cast<float>()); }
};

}  // namespace lt

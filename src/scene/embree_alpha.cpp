// EmbreeScene's alpha (embree_scene.h): which meshes get the Embree filter that
// discards hits where a MASK or BLEND material does not cover the surface, and
// the filter itself.
//
// The alpha at a hit is glTF's: the material's alpha (baseColorFactor[3]) times
// its base-colour texture's alpha (bilinear, with the texture's wrap modes and
// KHR_texture_transform, as the renderer reads the base colour) times the
// vertex colour's alpha, interpolated with Embree's barycentrics.
//   MASK:  the surface is there where alpha >= alphaCutoff.
//   BLEND: alpha is coverage: a ray meets the surface with probability alpha,
//          decided by a hash of the ray (origin, direction) and the triangle
//          (instance, primitive). The decision is a function of the query alone:
//          the same ray gives the same answer in Intersect and Occluded, on any
//          thread, in any order; the rays of different samples (which differ)
//          decide independently, so their average is the alpha blend.
#include <algorithm>
#include <cstring>

#include "core/random.h"
#include "scene/embree_scene.h"

namespace lt {

namespace {

uint64_t Bits(float a, float b) {
  uint32_t x, y;
  std::memcpy(&x, &a, 4);
  std::memcpy(&y, &b, 4);
  return (uint64_t(x) << 32) | y;
}

// Whether the material, at alpha `min_alpha` (its smallest), lets a ray through.
bool MayPass(const Material& m, float min_alpha) {
  switch (m.alpha_mode) {
    case AlphaMode::kMask: return min_alpha < m.alpha_cutoff;
    case AlphaMode::kBlend: return min_alpha < 1.0f;
    case AlphaMode::kOpaque:
    default: return false;
  }
}

}  // namespace

bool EmbreeScene::MeshNeedsAlphaFilter(size_t mesh_index) const {
  if (material_min_alpha_.empty()) return false;  // every material opaque: the common case
  const SceneGeometry& g = *geometry_;
  const Mesh& mesh = g.meshes[mesh_index];
  float vertex_min = 1.0f;
  for (float a : mesh.alphas) vertex_min = std::min(vertex_min, a);
  auto may_pass = [&](size_t material) {
    return MayPass(g.materials[material], material_min_alpha_[material] * vertex_min);
  };
  bool own_materials = false;
  for (const SceneInstance& inst : g.instances) {
    if (inst.mesh != mesh_index) continue;
    if (inst.material_override < 0) {
      own_materials = true;
    } else if (may_pass(size_t(inst.material_override))) {
      return true;
    }
  }
  if (!own_materials) return false;
  std::vector<char> seen(g.materials.size(), 0);
  for (uint32_t m : mesh.triangle_material) {
    if (seen[m]) continue;
    seen[m] = 1;
    if (may_pass(m)) return true;
  }
  return false;
}

size_t EmbreeScene::alpha_filtered_mesh_count() const {
  return size_t(std::count(mesh_alpha_filtered_.begin(), mesh_alpha_filtered_.end(), 1));
}

bool EmbreeScene::Covers(uint32_t instance_id, uint32_t primitive_id, float u, float v, const float ray[6]) const {
  const SceneGeometry& g = *geometry_;
  const SceneInstance& inst = g.instances[instance_id];
  const Material& mat = g.materials[g.MaterialOf(inst, primitive_id)];
  if (mat.alpha_mode == AlphaMode::kOpaque) return true;
  const Mesh& mesh = g.meshes[inst.mesh];
  const uint32_t* tri = &mesh.indices[3 * size_t(primitive_id)];
  const float w = 1.0f - u - v;
  Eigen::Vector2f uv = Eigen::Vector2f::Zero();
  if (!mesh.texcoords.empty()) uv = w * mesh.texcoords[tri[0]] + u * mesh.texcoords[tri[1]] + v * mesh.texcoords[tri[2]];
  float alpha = mat.AlphaAt(uv);
  if (!mesh.alphas.empty()) alpha *= w * mesh.alphas[tri[0]] + u * mesh.alphas[tri[1]] + v * mesh.alphas[tri[2]];
  if (mat.alpha_mode == AlphaMode::kMask) return alpha >= mat.alpha_cutoff;
  if (alpha >= 1.0f) return true;
  if (!(alpha > 0.0f)) return false;
  const uint64_t key = HashKey(Bits(ray[0], ray[1]), Bits(ray[2], ray[3]), Bits(ray[4], ray[5]),
                               (uint64_t(instance_id) << 32) | primitive_id, 0x616c706861ull /* "alpha" */);
  const float xi = float(key >> 40) * 0x1p-24f;  // uniform in [0, 1)
  return xi < alpha;
}

void EmbreeScene::AlphaFilter(const RTCFilterFunctionNArguments* args) {
  const auto* self = static_cast<const EmbreeScene*>(args->geometryUserPtr);
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const float ray[6] = {RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i),
                          RTCRayN_org_z(args->ray, n, i), RTCRayN_dir_x(args->ray, n, i),
                          RTCRayN_dir_y(args->ray, n, i), RTCRayN_dir_z(args->ray, n, i)};
    if (!self->Covers(RTCHitN_instID(args->hit, n, i, 0), RTCHitN_primID(args->hit, n, i), RTCHitN_u(args->hit, n, i),
                      RTCHitN_v(args->hit, n, i), ray)) {
      args->valid[i] = 0;
    }
  }
}

}  // namespace lt

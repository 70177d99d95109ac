// The loaded scene as an Embree ray-tracing scene, with instancing: one Embree
// triangle geometry (in its own scene) per mesh, instanced once per SceneInstance.
//
// Precision: Embree works in float. To keep millimetre-scale geometry exact up to
// 1 km from the world origin, Embree holds the "render frame": the world
// translated by a double offset `render_origin()` (the centre of the scene
// bounds). Instance transforms are composed in double (render_from_world *
// world_from_mesh) and only then cast to float. Hits are reported in the world
// frame, refined in double (the ray intersected with the hit triangle, its
// corners transformed by the instance's double transform), so their accuracy
// does not depend on the distance from the origin or on Embree's float arithmetic.
//
// Embree device errors become exceptions (std::runtime_error), never ignored.
//
// Meshes that change over time (the printed part growing while it is scanned):
// a scene built from mutable geometry (the shared_ptr<SceneGeometry> constructor)
// can replace one mesh's triangles with ReplaceMesh. Only that mesh's Embree
// scene is rebuilt, and the top scene refitted over the instances; other meshes
// are untouched. The render origin stays where construction put it. A mesh may be
// empty (no triangles): it is instanced but nothing is hit.
//
// Alpha (glTF alphaMode, Material::alpha_mode): a mesh whose materials may let
// light through somewhere (MASK with some alpha below the cutoff, BLEND with
// some alpha below 1; alpha = factor x texture x vertex alpha) gets an Embree
// intersection and occlusion filter that discards the hits the surface does not
// cover (embree_alpha.cpp). Every query (Intersect, Occluded, and callers of
// handle()) so sees the same surface. Meshes without such materials get no
// filter: their rays run exactly the code they ran before.
#pragma once

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "scene/mesh.h"
#include "scene/scene_geometry.h"

namespace lt {

// A ray in the world frame: points origin + t * direction for t in [t_min, t_max].
struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // need not be unit length
  double t_min = 0;
  double t_max = std::numeric_limits<double>::infinity();
};

struct Hit {
  double t = 0;                           // ray parameter (in units of |direction|)
  Eigen::Vector3d position;               // world frame, metres
  Eigen::Vector3d geometric_normal;       // world, unit, front side (counter-clockwise winding)
  Eigen::Vector3d shading_normal;         // world, unit, interpolated vertex normal
  Eigen::Vector2f uv = Eigen::Vector2f::Zero();  // interpolated texture coordinates (0 when the mesh has none)
  Eigen::Vector3f vertex_color = Eigen::Vector3f::Ones();  // interpolated Mesh::colors (1 when the mesh has none)
  Eigen::Vector2f barycentric;            // (u, v): position = (1-u-v) p0 + u p1 + v p2 (refined in double)
  uint32_t material_id = 0;               // index into SceneGeometry::materials
  uint32_t instance_id = 0;               // index into SceneGeometry::instances
  uint32_t primitive_id = 0;              // triangle index within the instance's mesh
  bool front_face = true;                 // the ray arrived on the side geometric_normal points to
};

// The base colour at a hit: the material's (its texture at hit.uv) times the
// mesh's vertex colour there (glTF: COLOR_0 multiplies the base colour).
inline Eigen::Vector3f BaseColorAt(const Material& material, const Hit& hit) {
  return material.BaseColorAt(hit.uv).cwiseProduct(hit.vertex_color);
}

class EmbreeScene {
 public:
  // Builds the Embree scene. The geometry is shared (Embree reads its index
  // buffers in place), so it stays alive as long as this object.
  explicit EmbreeScene(std::shared_ptr<const SceneGeometry> geometry);
  // The same, for geometry whose meshes may later be replaced (ReplaceMesh).
  explicit EmbreeScene(std::shared_ptr<SceneGeometry> geometry);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // The nearest hit along the ray, if any. Thread-safe.
  std::optional<Hit> Intersect(const Ray& ray) const;
  // Whether anything lies on the ray within [t_min, t_max]. Thread-safe.
  bool Occluded(const Ray& ray) const;
  // Intersect for many rays, in parallel (hits.size() must equal rays.size()).
  void IntersectMany(std::span<const Ray> rays, std::span<std::optional<Hit>> hits) const;

  // The world point the render frame's origin sits at; render = world - render_origin.
  const Eigen::Vector3d& render_origin() const { return render_origin_; }
  Eigen::Vector3d RenderFromWorld(const Eigen::Vector3d& p_in_world) const { return p_in_world - render_origin_; }
  Eigen::Vector3d WorldFromRender(const Eigen::Vector3d& p_in_render) const { return p_in_render + render_origin_; }
  // The Embree scene (render frame). For callers that trace rays themselves.
  RTCScene handle() const { return scene_; }

  const SceneGeometry& geometry() const { return *geometry_; }
  // Exact world bounds of all instanced geometry (empty box for an empty scene).
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }
  size_t triangle_count() const { return geometry_->InstancedTriangleCount(); }
  size_t unique_triangle_count() const { return geometry_->UniqueTriangleCount(); }
  size_t instance_count() const { return geometry_->instances.size(); }
  size_t degenerate_triangle_count() const { return geometry_->degenerate_triangles; }
  // Meshes whose triangles carry the alpha filter (0 for a scene without MASK or BLEND).
  size_t alpha_filtered_mesh_count() const;
  const std::vector<std::string>& warnings() const { return geometry_->warnings; }

  // Whether ReplaceMesh may be called (built from mutable geometry).
  bool mutable_geometry() const { return mutable_geometry_ != nullptr; }
  // Replaces the triangles of SceneGeometry::meshes[mesh_index] (every instance
  // of it sees the new mesh) and rebuilds what depends on it. Not thread-safe:
  // no query may run meanwhile. Throws std::logic_error on immutable geometry,
  // std::out_of_range for a bad index, std::logic_error (Mesh::Validate) for an
  // inconsistent mesh. Bounds grow to hold the new mesh (they never shrink).
  void ReplaceMesh(size_t mesh_index, Mesh mesh);

  // Fills a hit from what Embree reports (instance, triangle, barycentrics).
  Hit MakeHit(const Ray& ray, uint32_t instance_id, uint32_t primitive_id, float u, float v) const;
  // Throws std::runtime_error when Embree has reported an error on this scene's
  // device. Construction calls it; code that calls Embree on handle() directly
  // calls it after its own Embree calls.
  void CheckDevice() const { ThrowIfError("using the scene"); }

 private:
  struct DeviceErrors;
  void ThrowIfError(const char* stage) const;
  void Build();
  // Builds mesh_scenes_[mesh_index]'s content; returns the re-centring offset.
  Eigen::Vector3d BuildMeshScene(size_t mesh_index);
  void SetInstanceTransform(size_t instance_index, RTCGeometry geom) const;
  // Alpha (embree_alpha.cpp): whether a mesh needs the filter, the filter, and
  // whether a candidate hit is on the surface (`ray` in the frame Embree gives).
  bool MeshNeedsAlphaFilter(size_t mesh_index) const;
  static void AlphaFilter(const RTCFilterFunctionNArguments* args);
  bool Covers(uint32_t instance_id, uint32_t primitive_id, float u, float v, const float ray[6]) const;

  std::shared_ptr<const SceneGeometry> geometry_;
  SceneGeometry* mutable_geometry_ = nullptr;  // the same geometry, when it may change
  std::unique_ptr<DeviceErrors> errors_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<RTCScene> mesh_scenes_;
  std::vector<char> mesh_attached_;                // per mesh: its scene holds geometry 0
  std::vector<Eigen::Vector3d> mesh_center_;       // per mesh: the re-centring offset (float-exact)
  std::vector<Eigen::Matrix3d> normal_from_mesh_;  // inverse transpose of each instance's linear part
  std::vector<float> material_min_alpha_;          // per material: MinAlpha() (1 when opaque); empty when all are opaque
  std::vector<char> mesh_alpha_filtered_;          // per mesh: its geometry has the alpha filter
  Eigen::Vector3d render_origin_ = Eigen::Vector3d::Zero();
  Eigen::AlignedBox3d bounds_;
};

}  // namespace lt

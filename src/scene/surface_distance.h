// Exact point-to-surface distance: the nearest point on a set of triangles (world
// frame, double precision) found over a bounding volume hierarchy, and the
// surfaces of a scene file at a given time (every object's instances, plus the
// printed part grown to that time as the renderer grows it, scene/printed_part.h).
// `lasertwin eval` scores a measured point by its distance to these surfaces
// (docs/evaluation.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "scene/mesh.h"

namespace lt {

struct SceneFile;
struct SceneGeometry;
class PrintedPart;

// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision
// Detection, 5.1.5). A degenerate triangle gives the nearest point of its edges.
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

// Triangles in the world frame and a bounding volume hierarchy over them.
class TriangleSet {
 public:
  // Adds a mesh's triangles placed by world_from_mesh (composed in double).
  void Add(const Mesh& mesh, const Eigen::Affine3d& world_from_mesh);
  void Clear();
  // Builds the hierarchy; call after the last Add and before ClosestPoint.
  void Build();
  size_t size() const { return corners_.size() / 3; }
  // The nearest point on any triangle to p; nullopt when the set is empty.
  std::optional<Eigen::Vector3d> ClosestPoint(const Eigen::Vector3d& p) const;

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int first = 0, count = 0;  // a leaf: triangles order_[first, first + count)
    int left = -1, right = -1; // an inner node: its children
  };
  int BuildNode(int first, int count, std::vector<Eigen::Vector3d>& centroids);
  std::vector<Eigen::Vector3d> corners_;  // 3 per triangle
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

// The surfaces of a scene at a sequence time.
class SceneSurface {
 public:
  explicit SceneSurface(const SceneFile& scene);  // loads the glTF files (lt::InputError naming them)
  ~SceneSurface();
  // Grows the printed part to sequence time t (the frame's mid-exposure, as the
  // renderer does); nothing to do for a scene without "print". As the renderer
  // (PrintedPart::UpdateTo), it meshes only what changed: the chunks complete at t
  // are one triangle set, to which a chunk is added when printing passes it (the
  // set is made again only when time goes back), and the growing chunks another,
  // made at every new time.
  void UpdateTo(double sequence_time_s);
  // Distance from p to the nearest surface; nullopt when the scene has no triangle.
  std::optional<double> Distance(const Eigen::Vector3d& p_in_world) const;
  size_t triangle_count() const { return fixed_.size() + complete_.size() + growing_.size(); }
  // Chunk meshes made by the updates so far (complete chunks are made once).
  size_t chunk_meshes_made() const { return chunk_meshes_made_; }

 private:
  void AddChunk(size_t chunk, double gcode_time_s, TriangleSet* set);
  std::unique_ptr<SceneGeometry> geometry_;
  std::unique_ptr<PrintedPart> part_;
  TriangleSet fixed_, complete_, growing_;
  std::vector<bool> in_complete_;  // per chunk: its final mesh is in complete_
  std::optional<double> print_time_;
  size_t chunk_meshes_made_ = 0;
};

}  // namespace lt

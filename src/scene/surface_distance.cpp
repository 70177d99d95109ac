#include "scene/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

#include "scene/motion.h"
#include "scene/printed_part.h"
#include "scene/scene_file.h"
#include "scene/scene_geometry.h"

namespace lt {

Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double sum = va + vb + vc;
  if (!(sum > 0)) {  // degenerate: the nearest of the three edges
    auto on_segment = [&](const Eigen::Vector3d& s, const Eigen::Vector3d& e) {
      const Eigen::Vector3d d = e - s;
      const double l2 = d.squaredNorm();
      return l2 > 0 ? Eigen::Vector3d(s + d * std::clamp((p - s).dot(d) / l2, 0.0, 1.0)) : s;
    };
    Eigen::Vector3d best = on_segment(a, b);
    for (const Eigen::Vector3d& q : {on_segment(b, c), on_segment(c, a)})
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    return best;
  }
  return a + ab * (vb / sum) + ac * (vc / sum);
}

void TriangleSet::Add(const Mesh& mesh, const Eigen::Affine3d& world_from_mesh) {
  corners_.reserve(corners_.size() + mesh.indices.size());
  for (uint32_t i : mesh.indices) corners_.push_back(world_from_mesh * mesh.positions[i].cast<double>());
  nodes_.clear();
}

void TriangleSet::Clear() {
  corners_.clear();
  order_.clear();
  nodes_.clear();
}

void TriangleSet::Build() {
  const int n = int(size());
  order_.resize(size_t(n));
  std::vector<Eigen::Vector3d> centroids(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    order_[size_t(i)] = i;
    centroids[size_t(i)] = (corners_[3 * size_t(i)] + corners_[3 * size_t(i) + 1] + corners_[3 * size_t(i) + 2]) / 3;
  }
  nodes_.clear();
  nodes_.reserve(size_t(2 * n / 4 + 2));
  if (n > 0) BuildNode(0, n, centroids);
}

int TriangleSet::BuildNode(int first, int count, std::vector<Eigen::Vector3d>& centroids) {
  const int id = int(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box, centre_box;
  for (int k = first; k < first + count; ++k) {
    const size_t t = size_t(order_[size_t(k)]);
    for (int j = 0; j < 3; ++j) box.extend(corners_[3 * t + size_t(j)]);
    centre_box.extend(centroids[t]);
  }
  nodes_[size_t(id)].box = box;
  constexpr int kLeaf = 4;
  if (count <= kLeaf) {
    nodes_[size_t(id)].first = first, nodes_[size_t(id)].count = count;
    return id;
  }
  int axis = 0;
  centre_box.sizes().maxCoeff(&axis);
  const int half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](int x, int y) { return centroids[size_t(x)][axis] < centroids[size_t(y)][axis]; });
  const int left = BuildNode(first, half, centroids);
  const int right = BuildNode(first + half, count - half, centroids);
  nodes_[size_t(id)].left = left, nodes_[size_t(id)].right = right;
  return id;
}

std::optional<Eigen::Vector3d> TriangleSet::ClosestPoint(const Eigen::Vector3d& p) const {
  if (nodes_.empty()) return std::nullopt;
  double best_d2 = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  std::vector<std::pair<double, int>> stack = {{nodes_[0].box.squaredExteriorDistance(p), 0}};
  while (!stack.empty()) {
    const auto [d2, id] = stack.back();
    stack.pop_back();
    if (d2 >= best_d2) continue;
    const Node& node = nodes_[size_t(id)];
    if (node.left < 0) {
      for (int k = node.first; k < node.first + node.count; ++k) {
        const size_t t = size_t(order_[size_t(k)]);
        const Eigen::Vector3d q = ClosestPointOnTriangle(p, corners_[3 * t], corners_[3 * t + 1], corners_[3 * t + 2]);
        const double e = (q - p).squaredNorm();
        if (e < best_d2) best_d2 = e, best = q;
      }
      continue;
    }
    const double dl = nodes_[size_t(node.left)].box.squaredExteriorDistance(p);
    const double dr = nodes_[size_t(node.right)].box.squaredExteriorDistance(p);
    // The nearer child is popped first.
    if (dl < dr) {
      stack.emplace_back(dr, node.right), stack.emplace_back(dl, node.left);
    } else {
      stack.emplace_back(dl, node.left), stack.emplace_back(dr, node.right);
    }
  }
  return best;
}

SceneSurface::SceneSurface(const SceneFile& scene)
    : geometry_(std::make_unique<SceneGeometry>(LoadSceneGeometry(scene))) {
  const SceneGeometry& g = *geometry_;
  for (const SceneInstance& inst : g.instances) {
    if (std::find(g.print_meshes.begin(), g.print_meshes.end(), inst.mesh) != g.print_meshes.end()) continue;
    fixed_.Add(g.meshes[inst.mesh], inst.world_from_mesh);
  }
  fixed_.Build();
  if (scene.print) {
    part_ = std::make_unique<PrintedPart>(std::get<GcodeMotion>(scene.motion), *scene.print, g.print_meshes);
  }
}

SceneSurface::~SceneSurface() = default;

void SceneSurface::AddChunk(size_t chunk, double gcode_time_s, TriangleSet* set) {
  const SceneGeometry& g = *geometry_;
  const Mesh mesh = part_->ChunkMeshAt(chunk, gcode_time_s);  // as PrintedPart::UpdateTo builds it
  ++chunk_meshes_made_;
  for (const SceneInstance& inst : g.instances)
    if (inst.mesh == g.print_meshes[chunk]) set->Add(mesh, inst.world_from_mesh);
}

void SceneSurface::UpdateTo(double sequence_time_s) {
  if (!part_) return;
  const double t = part_->GcodeTime(sequence_time_s);
  if (print_time_ && *print_time_ == t) return;
  const std::vector<PrintChunk>& chunks = part_->chunks();
  using State = PrintChunk::State;
  in_complete_.resize(chunks.size(), false);
  for (size_t c = 0; c < chunks.size(); ++c) {
    if (in_complete_[c] && chunks[c].StateAt(t) != State::kComplete) {  // time went back past a chunk's end
      complete_.Clear();
      in_complete_.assign(chunks.size(), false);
      break;
    }
  }
  bool complete_changed = false;
  growing_.Clear();
  for (size_t c = 0; c < chunks.size(); ++c) {
    const State state = chunks[c].StateAt(t);
    if (state == State::kComplete) {
      if (in_complete_[c]) continue;
      AddChunk(c, t, &complete_);
      in_complete_[c] = true;
      complete_changed = true;
    } else if (state == State::kGrowing) {
      AddChunk(c, t, &growing_);
    }
  }
  if (complete_changed) complete_.Build();
  growing_.Build();
  print_time_ = t;
}

std::optional<double> SceneSurface::Distance(const Eigen::Vector3d& p_in_world) const {
  std::optional<double> d;
  for (const TriangleSet* set : {&fixed_, &complete_, &growing_}) {
    if (auto q = set->ClosestPoint(p_in_world)) {
      const double e = (*q - p_in_world).norm();
      if (!d || e < *d) d = e;
    }
  }
  return d;
}

}  // namespace lt

#include "render/laser_entry_tree.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <set>
#include <span>

#include "render/specular_albedo.h"

namespace lt {

namespace {

// A new segment starts where the normal turns by more than ~25 degrees or
// neighbouring hits are farther apart than kSegmentGap patch sizes.
constexpr double kSegmentCos = 0.9;
constexpr double kSegmentGap = 4.0;
// Relative margin of the reach by which Sum prunes a node (r_max + its radius).
constexpr double kRadiusMargin = 1e-4;
// A node splits by its normals, not in grid order, when its normal box is
// wider than kNormalSpread on some axis and it straddles (n . n_o < 0 for some
// of its normals and > 0 for others, beyond kStraddleCos) for one of the
// tree's normals, as do both halves a split in grid order would give.
constexpr float kNormalSpread = 0.25f;
constexpr float kStraddleCos = 0.02f;

LaserEntryTree::Moment ToMoment(const Eigen::Matrix3d& m) {
  return {float(m(0, 0)), float(m(1, 1)), float(m(2, 2)), float(m(0, 1)), float(m(0, 2)), float(m(1, 2))};
}

Eigen::Matrix3d FromMoment(const LaserEntryTree::Moment& m) {
  Eigen::Matrix3d out;
  out << m[0], m[3], m[4], m[3], m[1], m[5], m[4], m[5], m[2];
  return out;
}

}  // namespace

// Accumulates the entry points of one segment: weight, weighted position and
// second moment (each point a disc of its patch's area), normals.
struct LaserEntryTree::Segment {
  double w = 0;
  Eigen::Vector3d wp = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
  Eigen::Matrix3d wpp = Eigen::Matrix3d::Zero(), disc = Eigen::Matrix3d::Zero();
  Eigen::Vector3d n0 = Eigen::Vector3d::Zero();
  uint32_t material = 0;
  void Add(const Eigen::Vector3d& p, const Eigen::Vector3d& ni, double wi, double disc_m2) {
    w += wi;
    wp += wi * p;
    wpp += wi * p * p.transpose();
    // A disc's moment: disc_m2 / 2 along each axis in its plane.
    disc += (0.5 * wi * disc_m2) * (Eigen::Matrix3d::Identity() - ni * ni.transpose());
    n += wi * ni;
  }
  void Flush(std::vector<Point>* out) {
    if (w > 0) {
      Point pt;
      const Eigen::Vector3d c = wp / w;
      pt.p = c.cast<float>();
      pt.n = n.normalized().cast<float>();
      pt.w = float(w);
      pt.m = ToMoment((wpp + disc) / w - c * c.transpose());
      pt.material = material;
      out->push_back(pt);
    }
    *this = Segment();
  }
};

std::unique_ptr<LaserEntryTree> LaserEntryTree::Build(const EmbreeScene& scene, const PointEmitter& e, int sheet,
                                                      const SheetWindow& window, double spacing_m, uint64_t* rays) {
  if (!e.laser || window.empty() || !(spacing_m > 0) || !(window.r_far > 0)) return nullptr;
  const LaserProjector& laser = *e.laser;
  auto tree = std::unique_ptr<LaserEntryTree>(new LaserEntryTree());
  tree->origin_ = e.origin_world;
  tree->projector_from_world_ = e.projector_from_world.linear();
  tree->laser_ = &laser;
  tree->sheet_ = sheet;
  tree->window_ = window;
  const Eigen::Matrix3d world_from_projector = tree->projector_from_world_.transpose();
  const std::vector<Material>& materials = scene.geometry().materials;

  const double dphi = spacing_m / window.r_far;
  const size_t n_phi = size_t(std::ceil((window.phi_hi - window.phi_lo) / dphi));
  if (n_phi == 0 || n_phi > kMaxPoints) return nullptr;
  std::vector<std::vector<Point>> rows(n_phi);
  std::atomic<size_t> total{0};
  std::atomic<uint64_t> cast{0};
  std::atomic<bool> overflow{false};
  tbb::parallel_for(size_t(0), n_phi, [&](size_t i) {
    if (overflow.load(std::memory_order_relaxed)) return;
    const double phi = window.phi_lo + (double(i) + 0.5) * dphi;
    auto cast_psi = [&](double psi) {
      Ray ray{e.origin_world, world_from_projector * laser.DirectionAt(sheet, phi, psi), 0, INFINITY};
      return scene.Intersect(ray);
    };
    uint64_t local_rays = 1;
    const auto central = cast_psi(0.0);
    const double r0 = central ? (central->position - e.origin_world).norm() : window.r_far;
    const double sigma = laser.SheetSigma(r0);
    const double dpsi = std::min(0.5 * sigma, spacing_m / r0);
    const long half = long(std::ceil(kAcrossSigmas * sigma / dpsi));
    const long group = std::max(1L, std::lround(kSegmentSigmas * sigma / dpsi));  // psi samples per segment
    if (total.fetch_add(size_t(2 * half + 1)) + size_t(2 * half + 1) > kMaxPoints) {
      overflow = true;
      return;
    }
    // Entry points across the sheet, in psi order, merged into segments: runs
    // of neighbouring hits on one surface (same material, similar normal, no gap).
    std::vector<Point>& row = rows[i];
    Segment seg;
    Eigen::Vector3d last_p = Eigen::Vector3d::Zero();
    double last_size = 0;
    for (long j = -half; j <= half; ++j) {
      const double psi = double(j) * dpsi;
      std::optional<Hit> hit = j == 0 ? central : cast_psi(psi);
      local_rays += j != 0;
      const Material* m = hit ? &materials[hit->material_id] : nullptr;
      if (!m || !m->subsurface) {
        seg.Flush(&row);
        continue;
      }
      const Eigen::Vector3d to = e.origin_world - hit->position;
      const double r = to.norm();
      Eigen::Vector3d ni = hit->geometric_normal;
      double cos_i = ni.dot(to) / r;
      if (cos_i < 0) ni = -ni, cos_i = -cos_i;
      if (!(cos_i > 0)) continue;
      const double intensity =
          laser.SheetIntensityAt(sheet, tree->projector_from_world_ * (hit->position - e.origin_world));
      const double d_omega = std::cos(psi) * dpsi * dphi;
      const double power = intensity * d_omega * e.weight;
      const double area = r * r * d_omega / std::max(cos_i, 1e-3);
      const double size = std::sqrt(area);
      if (seg.w > 0 && ((j + half) % group == 0 || hit->material_id != seg.material || ni.dot(seg.n0) < kSegmentCos ||
                        (hit->position - last_p).norm() > kSegmentGap * std::max(size, last_size))) {
        seg.Flush(&row);
      }
      last_p = hit->position;
      last_size = size;
      if (!(power > 0)) continue;
      const float alpha = std::max(m->roughness * m->roughness, kMinGgxAlpha);
      const double w = power * (1.0 - DielectricSpecularAlbedo(float(std::min(cos_i, 1.0)), alpha));
      if (seg.w == 0) seg.material = hit->material_id, seg.n0 = ni;
      seg.Add(hit->position - e.origin_world, ni, w, area / (2.0 * M_PI));
    }
    seg.Flush(&row);
    cast.fetch_add(local_rays, std::memory_order_relaxed);
  });
  if (rays) *rays += cast.load();
  if (overflow) return nullptr;
  std::vector<Point> pts;
  for (auto& row : rows) pts.insert(pts.end(), row.begin(), row.end());
  tree->points_ = pts.size();
  if (pts.empty()) return tree;
  tree->nodes_.reserve(2 * pts.size());
  tree->moments_.reserve(2 * pts.size());
  tree->BuildNode(pts, 0, pts.size(), DistinctNormals(pts));
  return tree;
}

// The segments' normals, one per cell of a 0.25 grid on each axis: the normals
// of the points a query will most likely be made at.
std::vector<Eigen::Vector3f> LaserEntryTree::DistinctNormals(const std::vector<Point>& pts) {
  std::set<std::array<long, 3>> cells;
  std::vector<Eigen::Vector3f> out;
  for (const Point& p : pts) {
    const std::array<long, 3> cell = {std::lround(4 * p.n.x()), std::lround(4 * p.n.y()), std::lround(4 * p.n.z())};
    if (cells.insert(cell).second) out.push_back(p.n);
  }
  return out;
}

LaserEntryTree::Node LaserEntryTree::NormalBox(std::span<const Point> pts) {
  Node box;
  box.n_lo = Eigen::Vector3f::Constant(INFINITY), box.n_hi = Eigen::Vector3f::Constant(-INFINITY);
  for (const Point& p : pts) box.n_lo = box.n_lo.cwiseMin(p.n), box.n_hi = box.n_hi.cwiseMax(p.n);
  return box;
}

bool LaserEntryTree::Straddles(const Node& box, std::span<const Eigen::Vector3f> query_normals) {
  for (const Eigen::Vector3f& n : query_normals) {
    float lo, hi;
    CosBounds(box, n, &lo, &hi);
    if (lo < -kStraddleCos && hi > kStraddleCos) return true;
  }
  return false;
}

uint32_t LaserEntryTree::BuildNode(std::vector<Point>& pts, size_t begin, size_t end,
                                   std::span<const Eigen::Vector3f> query_normals) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.emplace_back();
  moments_.emplace_back();
  Node node;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = Eigen::Vector3f::Constant(-INFINITY);
  node.n_lo = Eigen::Vector3f::Constant(INFINITY);
  node.n_hi = Eigen::Vector3f::Constant(-INFINITY);
  Eigen::Vector3d wp = Eigen::Vector3d::Zero();
  double w = 0;
  node.material = int32_t(pts[begin].material);
  for (size_t i = begin; i < end; ++i) {
    const Point& p = pts[i];
    lo = lo.cwiseMin(p.p);
    hi = hi.cwiseMax(p.p);
    node.n_lo = node.n_lo.cwiseMin(p.n);
    node.n_hi = node.n_hi.cwiseMax(p.n);
    wp += double(p.w) * p.p.cast<double>();
    w += p.w;
    if (int32_t(p.material) != node.material) node.material = -1;
  }
  node.w = float(w);
  const Eigen::Vector3d c = w > 0 ? Eigen::Vector3d(wp / w) : 0.5 * (lo + hi).cast<double>();
  node.c = c.cast<float>();
  // Parallel axes: each point's own moment plus its offset from c.
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  double radius = 0;
  for (size_t i = begin; i < end; ++i) {
    const Point& p = pts[i];
    const Eigen::Vector3d d = p.p.cast<double>() - c;
    m += double(p.w) * (FromMoment(p.m) + d * d.transpose());
    radius = std::max(radius, (p.p.cast<double>() - node.c.cast<double>()).norm());
  }
  if (w > 0) m /= w;
  const Moment moment = ToMoment(m);
  node.m2 = std::max(0.0f, moment[0] + moment[1] + moment[2]);
  // Sum prunes a node beyond r_max + radius; the margin is far above float
  // rounding, so no entry point within r_max is ever pruned.
  node.radius = float(radius * (1.0 + kRadiusMargin));
  moments_[index] = moment;
  if (end - begin == 1) {
    nodes_[index] = node;
    return index;
  }
  // In grid order (halves of the segments: nearby rows of the sheet), unless
  // the node mixes normals that face both ways from a query's and its halves
  // would too (a printed bead's flanks, each row holding both): then at the
  // middle of its widest normal axis, the grid order kept on either side. A
  // node that straddles is opened by every query it is in reach of; split
  // by position, each of the beads' nodes would, down to their segments.
  // Depth: a normal split halves the node's widest normal axis, at most 3
  // times each axis (from 2 down to kNormalSpread), and the grid splits halve
  // the count (at most 22 times, kMaxPoints): within Sum's stack of 64.
  size_t mid = begin + (end - begin) / 2;
  int axis = 0;
  const std::span<const Point> all(pts.data() + begin, end - begin);
  if ((node.n_hi - node.n_lo).maxCoeff(&axis) > kNormalSpread && Straddles(node, query_normals) &&
      Straddles(NormalBox(all.first(mid - begin)), query_normals) &&
      Straddles(NormalBox(all.subspan(mid - begin)), query_normals)) {
    const float cut = 0.5f * (node.n_lo[axis] + node.n_hi[axis]);
    mid = size_t(std::stable_partition(pts.begin() + long(begin), pts.begin() + long(end),
                                       [&](const Point& p) { return p.n[axis] < cut; }) -
                 pts.begin());
  }
  BuildNode(pts, begin, mid, query_normals);
  node.right = BuildNode(pts, mid, end, query_normals);
  nodes_[index] = node;
  return index;
}

// R(r) = A (t^3 + t) / (8 pi d r), t = exp(-r / (3 d)): BurleyProfile::Evaluate
// in float, for the hot path, at a node's centroid d = c - x (r2 = |d|^2)
// with the second-order term where the node is small seen from x. Within
// s = sqrt(kSmoothing m2) of a node's centroid, the profile's light inside
// radius s spread evenly over the disc: A CDF(s) / (pi s^2).
struct LaserEntryTree::Kernel {
  const BurleyProfile& profile;
  float opening2, inv_3d, scale;
  Kernel(const BurleyProfile& p, double opening_ratio)
      : profile(p),
        opening2(float(opening_ratio * opening_ratio)),
        inv_3d(float(1.0 / (3.0 * p.d()))),
        scale(float(p.albedo() / (8.0 * M_PI * p.d()))) {}
  float operator()(const Node& node, const Moment& m, const Eigen::Vector3f& d, float r2) const {
    const float s2 = kSmoothing * node.m2;
    if (r2 >= s2 && r2 > 0) {
      const float r = std::sqrt(r2), t = std::exp(-r * inv_3d), t3 = t * t * t;
      const float value = scale * (t3 + t) / r;
      // The expansion holds where the node is small seen from x (the
      // opening test); a leaf nearer than that is taken at its centroid.
      if (!(node.m2 < opening2 * r2)) return value;
      const float q = (d.x() * (m[0] * d.x() + 2 * (m[3] * d.y() + m[4] * d.z())) +
                       d.y() * (m[1] * d.y() + 2 * m[5] * d.z()) + d.z() * m[2] * d.z()) / r2;
      const float br = r * inv_3d, ar = 3 * br;
      return std::max(0.0f, value + 0.5f * scale / (r2 * r) *
                                        (q * (t3 * (ar * ar + 3 * ar + 3) + t * (br * br + 3 * br + 3)) -
                                         node.m2 * (t3 * (ar + 1) + t * (br + 1))));
    }
    return s2 > 0 ? float(profile.albedo() * profile.Cdf(std::sqrt(s2)) / (M_PI * s2)) : 0.0f;
  }
};

// Bounds of n . n_o over a node's normals, from their bounding box (a leaf's:
// its normal). Entry points count where n . n_o >= 0.
void LaserEntryTree::CosBounds(const Node& node, const Eigen::Vector3f& n_o, float* cos_lo, float* cos_hi) {
  *cos_lo = 0, *cos_hi = 0;
  for (int i = 0; i < 3; ++i) {
    const float a = n_o[i] * node.n_lo[i], b = n_o[i] * node.n_hi[i];
    *cos_lo += std::min(a, b), *cos_hi += std::max(a, b);
  }
}

double LaserEntryTree::Sum(const Eigen::Vector3d& x_world, const Eigen::Vector3d& n_world, uint32_t material,
                           const BurleyProfile& profile, double r_max, double opening_ratio,
                           int64_t* evaluated) const {
  if (nodes_.empty()) return 0.0;
  const Kernel R(profile, opening_ratio);
  const float opening2 = R.opening2;
  const float radius2 = float(kRadiusRatio * kRadiusRatio);
  const Eigen::Vector3f x = (x_world - origin_).cast<float>();
  const Eigen::Vector3f n_o = n_world.cast<float>();
  const float r_max2 = float(r_max) * float(r_max);
  // A node is pruned beyond r_max + its radius; the slack covers the rounding
  // of the float coordinates (relative to the projector) well above its size.
  const float reach = float(r_max * (1.0 + kRadiusMargin)) + 1e-6f * (x.cwiseAbs().maxCoeff() + float(r_max));
  const int32_t mat = int32_t(material);
  double sum = 0;
  std::array<uint32_t, 64> stack;
  int top = 0;
  uint32_t index = 0;
  for (;;) {
    const Node& node = nodes_[index];
    const Eigen::Vector3f d = node.c - x;
    const float r2 = d.squaredNorm(), limit = reach + node.radius;
    // Skipped: another material, beyond the profile's reach, or every entry
    // point lit on a face turned away.
    if (!(node.material >= 0 && node.material != mat) && !(r2 > limit * limit)) {
      float cos_lo, cos_hi;
      CosBounds(node, n_o, &cos_lo, &cos_hi);
      if (!(cos_hi < 0)) {
        // The centroid stands for an inner node only when its entry points
        // share one material, it is small seen from x (its second moment, and
        // its radius: a light segment far from the centroid may lie near x,
        // where R is steep) and all count; else descend (left child next, the
        // right one stacked).
        if (node.right != 0 && !(node.material >= 0 && node.m2 < opening2 * r2 &&
                                 node.radius * node.radius < radius2 * r2 && cos_lo >= 0)) {
          stack[top++] = node.right;
          ++index;
          continue;
        }
        if (r2 < r_max2) {
          sum += node.w * R(node, moments_[index], d, r2);
          if (evaluated) ++*evaluated;
        }
      }
    }
    if (top == 0) break;
    index = stack[--top];
  }
  return sum;
}

double LaserEntryTree::SumOverSegments(const Eigen::Vector3d& x_world, const Eigen::Vector3d& n_world,
                                       uint32_t material, const BurleyProfile& profile, double r_max,
                                       double leaf_opening_ratio) const {
  const Kernel R(profile, leaf_opening_ratio);
  const Eigen::Vector3f x = (x_world - origin_).cast<float>();
  const Eigen::Vector3f n_o = n_world.cast<float>();
  const float r_max2 = float(r_max) * float(r_max);
  double sum = 0;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Node& node = nodes_[i];
    if (node.right != 0 || node.material != int32_t(material)) continue;
    float cos_lo, cos_hi;
    CosBounds(node, n_o, &cos_lo, &cos_hi);
    const Eigen::Vector3f d = node.c - x;
    const float r2 = d.squaredNorm();
    if (!(cos_hi < 0) && r2 < r_max2) sum += node.w * R(node, moments_[i], d, r2);
  }
  return sum;
}

}  // namespace lt

#include "scene/bead_geometry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace lt {

namespace {

constexpr double kDefaultFilamentDiameterM = 1.75e-3;
constexpr double kMaxChordAngleRad = 10 * M_PI / 180;
constexpr double kMaxMitreTurnRad = M_PI / 2 + 1e-9;
constexpr double kLevelTolM = 1e-9;
constexpr double kSameAreaRel = 1e-4;

// One point of the cross-section outline: position across (y, horizontal, to the
// left of the direction of travel) and up (z) from the centroid, and its outward
// normal in that plane.
struct ProfilePoint {
  double y, z, ny, nz;
};

// The cross-section polygon of area `area` and height h (counter-clockwise in (y, z)),
// 2 (n_half + 1) points whatever its shape.
std::vector<ProfilePoint> Profile(double area, double h, int n_half) {
  std::vector<ProfilePoint> pts;
  const double w_stadium = area / h + h * (1 - M_PI / 4);
  const double half_straight = 0.5 * (w_stadium - h);
  if (half_straight > 1e-6 * h) {
    const double r = 0.5 * h;
    for (int side = 0; side < 2; ++side) {  // right end (+y), then left end (-y)
      const double cy = side == 0 ? half_straight : -half_straight;
      for (int k = 0; k <= n_half; ++k) {
        const double a = -M_PI / 2 + side * M_PI + M_PI * k / n_half;
        pts.push_back({cy + r * std::cos(a), r * std::sin(a), std::cos(a), std::sin(a)});
      }
    }
  } else {
    // As many points as the stadium has, so rings of either shape connect point to point.
    const double w = 4 * area / (M_PI * h);
    const int count = 2 * (n_half + 1);
    for (int k = 0; k < count; ++k) {
      const double a = -M_PI / 2 + 2 * M_PI * k / count;
      double ny = std::cos(a) / (0.5 * w), nz = std::sin(a) / (0.5 * h);
      const double n = std::hypot(ny, nz);
      pts.push_back({0.5 * w * std::cos(a), 0.5 * h * std::sin(a), ny / n, nz / n});
    }
  }
  // Widen so the polygon's area is exactly `area`.
  double poly = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const ProfilePoint& p = pts[i];
    const ProfilePoint& q = pts[(i + 1) % pts.size()];
    poly += p.y * q.z - q.y * p.z;
  }
  poly *= 0.5;
  const double s = area / poly;
  for (ProfilePoint& p : pts) {
    p.y *= s;
    const double ny = p.ny / s, n = std::hypot(ny, p.nz);
    p.ny = ny / n;
    p.nz /= n;
  }
  return pts;
}

double ProfileWidth(const std::vector<ProfilePoint>& profile) {
  double w = 0;
  for (const auto& p : profile) w = std::max(w, 2 * std::abs(p.y));
  return w;
}

// A straight piece of bead: its top centreline from a to b (the nozzle tip), its
// cross-section area and height, and whether it joins the piece before it.
struct Piece {
  Eigen::Vector3d a, b;
  double area = 0, h = 0;
  bool joins_previous = false;
  Eigen::Vector3d Direction() const {
    Eigen::Vector3d d(b.x() - a.x(), b.y() - a.y(), 0);
    return d.normalized();
  }
};

Eigen::Vector3d Side(const Eigen::Vector3d& d) { return Eigen::Vector3d(-d.y(), d.x(), 0); }

class MeshBuilder {
 public:
  MeshBuilder(Mesh& mesh, uint32_t material) : mesh_(mesh), material_(material) {}

  // A triangle wound so its normal points along `outward`.
  void Triangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                const Eigen::Vector3d& n0, const Eigen::Vector3d& n1, const Eigen::Vector3d& n2,
                const Eigen::Vector3d& outward) {
    const bool flip = (p1 - p0).cross(p2 - p0).dot(outward) < 0;
    Add(p0, n0);
    Add(flip ? p2 : p1, flip ? n2 : n1);
    Add(flip ? p1 : p2, flip ? n1 : n2);
    mesh_.triangle_material.push_back(material_);
  }
  // A flat convex polygon, as a fan.
  void Polygon(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& normal) {
    for (size_t i = 1; i + 1 < pts.size(); ++i) Triangle(pts[0], pts[i], pts[i + 1], normal, normal, normal, normal);
  }

 private:
  void Add(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    mesh_.indices.push_back(uint32_t(mesh_.positions.size()));
    mesh_.positions.push_back(p.cast<float>());
    mesh_.normals.push_back(n.cast<float>());
  }
  Mesh& mesh_;
  uint32_t material_;
};

// The ring of a cross-section at a joint point, on the plane spanned by the vertical
// and `across` (horizontal), with the widths scaled by `scale`.
std::vector<Eigen::Vector3d> Ring(const std::vector<ProfilePoint>& profile, const Eigen::Vector3d& top,
                                  double h, const Eigen::Vector3d& across, double scale) {
  std::vector<Eigen::Vector3d> ring;
  ring.reserve(profile.size());
  const Eigen::Vector3d centre = top - Eigen::Vector3d(0, 0, 0.5 * h);
  for (const auto& p : profile) ring.push_back(centre + across * (p.y * scale) + Eigen::Vector3d(0, 0, p.z));
  return ring;
}

// The mitre between pieces p (before) and q (after): the horizontal direction of
// the joint plane and the width scale 1 / cos(turn / 2).
void Mitre(const Piece& p, const Piece& q, Eigen::Vector3d& across, double& scale) {
  const Eigen::Vector3d s0 = Side(p.Direction()), s1 = Side(q.Direction());
  across = (s0 + s1).normalized();
  scale = 1.0 / across.dot(s0);
}

// Where nothing gives a rising bead its height (no stated height, no header layer
// height, no level: a spiral or non-planar path from its first move, as FullControl and
// robot slicers write them), the bead lies on the turn below it: the highest earlier
// such bead passing within kRadiusM of its start in the bed plane and at least
// kAwayM of beads back along the path (not the same turn's), else the bed (z 0).
class TurnsBelow {
 public:
  // The height of seg's bead above the turn below; records the bead for those above.
  double HeightOf(const ToolpathSegment& seg) {
    const Eigen::Vector3d p = seg.start_m;
    double below = 0;
    const auto [cx, cy] = Cell(p);
    for (long long i = cx - 1; i <= cx + 1; ++i) {
      for (long long j = cy - 1; j <= cy + 1; ++j) {
        auto it = cells_.find({i, j});
        if (it == cells_.end()) continue;
        for (const Sample& q : it->second) {
          if (length_m_ - q.along_m >= kAwayM && q.p.z() < p.z() - kLevelTolM &&
              std::hypot(q.p.x() - p.x(), q.p.y() - p.y()) <= kRadiusM) {
            below = std::max(below, q.p.z());
          }
        }
      }
    }
    const int n = std::max(1, int(std::ceil(seg.xy_length_m / kStepM)));
    for (int k = 0; k <= n; ++k) {
      const Eigen::Vector3d q = seg.PointAt(double(k) / n);
      cells_[Cell(q)].push_back({q, length_m_ + seg.xy_length_m * k / n});
    }
    length_m_ += seg.xy_length_m;
    return p.z() - below;
  }

 private:
  static constexpr double kRadiusM = 0.5e-3;  // about a bead's width: the turn below, not a neighbour line
  static constexpr double kAwayM = 4 * kRadiusM;
  static constexpr double kStepM = 0.25e-3;
  struct Sample {
    Eigen::Vector3d p;
    double along_m;  // bead length recorded before it
  };
  static std::pair<long long, long long> Cell(const Eigen::Vector3d& q) {
    return {(long long)std::floor(q.x() / kRadiusM), (long long)std::floor(q.y() / kRadiusM)};
  }
  std::map<std::pair<long long, long long>, std::vector<Sample>> cells_;
  double length_m_ = 0;
};

// The heights at which the path has extruded flat (level) beads, and the height of
// the last such level above the one below it.
struct Levels {
  std::set<double> z;
  double last_step = 0;
  TurnsBelow turns;
};

double LayerHeight(const Toolpath& path, const ToolpathSegment& seg, const BeadOptions& o, Levels& levels) {
  const double z = seg.start_m.z();
  // A bead rising along its move (spiral vase mode) lies on the turn below, one layer
  // height down, not on the last level: its height is the file's, else the last step.
  const bool rising = seg.end_m.z() - z > kLevelTolM;
  // Extrusion outside any layer (a start script's purge line, before the first layer
  // comment) is no level for the part's layers to stand on.
  const bool level = !rising && seg.layer != ToolpathSegment::kNoLayer;
  if (level) levels.z.insert(z);
  if (o.layer_height_m > 0) return o.layer_height_m;
  if (seg.height_m > 0) return seg.height_m;
  if (rising) {
    if (path.header_layer_height_m > 0) return path.header_layer_height_m;
    return levels.last_step > 0 ? levels.last_step : levels.turns.HeightOf(seg);
  }
  auto below = levels.z.lower_bound(z - kLevelTolM);
  double base = below == levels.z.begin() ? 0.0 : *std::prev(below);
  if (z - base > kLevelTolM) {
    if (level) levels.last_step = z - base;
    return z - base;
  }
  return path.header_layer_height_m;
}

}  // namespace

void BeadOptions::Check() const {
  if (!(std::isfinite(filament_diameter_m) && filament_diameter_m >= 0)) {
    throw std::invalid_argument("filament diameter must be >= 0 (0: from the file)");
  }
  if (!(std::isfinite(layer_height_m) && layer_height_m >= 0)) {
    throw std::invalid_argument("layer height must be >= 0 (0: from the file)");
  }
  if (points_per_half_disc < 2) throw std::invalid_argument("points_per_half_disc must be >= 2");
}

Mesh BeadMeshUpTo(const Toolpath& path, double t_s, const BeadOptions& options, BeadStats* stats) {
  options.Check();
  BeadStats st;
  const double d = options.filament_diameter_m > 0 ? options.filament_diameter_m
                   : path.filament_diameter_m > 0  ? path.filament_diameter_m
                                                   : kDefaultFilamentDiameterM;
  const double filament_area = M_PI * 0.25 * d * d;

  // The pieces, in order, with the segment each came from.
  std::vector<Piece> pieces;
  std::vector<size_t> origin;
  Levels levels;
  const std::vector<double>* heights = options.layer_heights;
  if (heights && heights->size() != path.segments.size()) {
    throw std::invalid_argument("BeadMeshUpTo: " + std::to_string(heights->size()) + " layer heights for " +
                                std::to_string(path.segments.size()) + " segments");
  }
  for (size_t k = heights ? options.first_segment : 0; k < path.segments.size(); ++k) {
    const ToolpathSegment& seg = path.segments[k];
    if (!(seg.t_start_s < t_s) || k >= options.end_segment) break;
    if (!seg.LaysBead()) continue;
    const double f = std::min(1.0, (t_s - seg.t_start_s) / seg.Duration());
    if (!(f > 0)) continue;
    const double h = heights ? (*heights)[k] : LayerHeight(path, seg, options, levels);
    if (k < options.first_segment) continue;  // seen for its level only
    if (!(h > 0)) {
      ++st.skipped;
      continue;
    }
    const double volume = filament_area * seg.laid_m * f;
    const int n = seg.arc ? std::max(1, int(std::ceil(std::abs(seg.sweep_rad) * f / kMaxChordAngleRad))) : 1;
    ++st.beads;
    for (int j = 0; j < n; ++j) {
      Piece p;
      p.a = j == 0 ? seg.start_m : seg.PointAt(f * j / n);
      p.b = (j + 1 == n && f == 1.0) ? seg.end_m : seg.PointAt(f * (j + 1) / n);
      const double chord = std::hypot(p.b.x() - p.a.x(), p.b.y() - p.a.y());
      if (!(chord > 1e-12)) continue;
      p.area = volume / n / chord;
      p.h = h;
      // Joins the previous piece when it continues it (same or next segment, which
      // extruded), at the same height, turning at most 90 degrees with room for the mitre.
      if (!pieces.empty() && (origin.back() == k || origin.back() + 1 == k) && pieces.back().h == h &&
          (pieces.back().b - p.a).norm() < 1e-12) {
        const Piece& q = pieces.back();
        const double turn = std::acos(std::clamp(q.Direction().dot(p.Direction()), -1.0, 1.0));
        const double chord_q = std::hypot(q.b.x() - q.a.x(), q.b.y() - q.a.y());
        const double half_width = 0.5 * std::max(ProfileWidth(Profile(q.area, h, 2)), ProfileWidth(Profile(p.area, h, 2)));
        const double offset = half_width * std::tan(0.5 * turn);
        if (turn <= kMaxMitreTurnRad && offset <= 0.5 * std::min(chord, chord_q)) {
          p.joins_previous = true;
          p.a = q.b;
          // Cross-sections this close would make a step too narrow to hold in float
          // coordinates (a few spacings of floats at this distance from the origin,
          // the width changing by about dA / h): take them equal.
          const double float_step = 16 * 1.2e-7 * (q.b.cwiseAbs().maxCoeff() + h);
          const double da = std::abs(p.area - q.area);
          if (da <= kSameAreaRel * q.area || da / h <= float_step) p.area = q.area;
        }
      }
      st.volume_m3 += p.area * chord;
      pieces.push_back(p);
      origin.push_back(k);
    }
  }

  Mesh mesh;
  mesh.name = "beads";
  MeshBuilder out(mesh, options.material);
  const int n_half = options.points_per_half_disc;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const Piece& p = pieces[i];
    const bool joins_next = i + 1 < pieces.size() && pieces[i + 1].joins_previous;
    const Eigen::Vector3d dir = p.Direction(), side = Side(dir), up(0, 0, 1);
    const std::vector<ProfilePoint> profile = Profile(p.area, p.h, n_half);
    Eigen::Vector3d across_start = side, across_end = side;
    double scale_start = 1, scale_end = 1;
    if (p.joins_previous) Mitre(pieces[i - 1], p, across_start, scale_start);
    if (joins_next) Mitre(p, pieces[i + 1], across_end, scale_end);
    const auto ring_a = Ring(profile, p.a, p.h, across_start, scale_start);
    const auto ring_b = Ring(profile, p.b, p.h, across_end, scale_end);
    if (!p.joins_previous) ++st.runs;
    // The side of the bead.
    const size_t m = profile.size();
    for (size_t k = 0; k < m; ++k) {
      const size_t k1 = (k + 1) % m;
      const Eigen::Vector3d n0 = side * profile[k].ny + up * profile[k].nz;
      const Eigen::Vector3d n1 = side * profile[k1].ny + up * profile[k1].nz;
      const Eigen::Vector3d outward = n0 + n1;
      out.Triangle(ring_a[k], ring_b[k], ring_b[k1], n0, n0, n1, outward);
      out.Triangle(ring_a[k], ring_b[k1], ring_a[k1], n0, n1, n1, outward);
    }
    if (!p.joins_previous) out.Polygon(ring_a, -dir);
    if (!joins_next) out.Polygon(ring_b, dir);
    // A step in cross-section where this piece meets the previous one.
    if (p.joins_previous && pieces[i - 1].area != p.area) {
      const Piece& q = pieces[i - 1];
      const auto ring_q = Ring(Profile(q.area, q.h, n_half), p.a, p.h, across_start, scale_start);
      Eigen::Vector3d normal = across_start.cross(up);
      if (normal.dot(dir) < 0) normal = -normal;
      if (p.area > q.area) normal = -normal;  // the larger ring is this piece's: it faces back
      for (size_t k = 0; k < m; ++k) {
        const size_t k1 = (k + 1) % m;
        out.Triangle(ring_q[k], ring_a[k], ring_a[k1], normal, normal, normal, normal);
        out.Triangle(ring_q[k], ring_a[k1], ring_q[k1], normal, normal, normal, normal);
      }
    }
  }
  if (stats) *stats = st;
  return mesh;
}

std::vector<double> BeadLayerHeights(const Toolpath& path, const BeadOptions& options) {
  options.Check();
  std::vector<double> heights(path.segments.size(), 0.0);
  Levels levels;
  for (size_t k = 0; k < path.segments.size(); ++k) {
    const ToolpathSegment& seg = path.segments[k];
    if (seg.LaysBead()) heights[k] = LayerHeight(path, seg, options, levels);
  }
  return heights;
}

double MeshVolume(const Mesh& mesh) {
  if (mesh.TriangleCount() == 0) return 0;
  // Relative to the centre of the mesh: with the origin far away the terms would be
  // large and cancel.
  const Eigen::Vector3d c = mesh.Bounds().center();
  double v = 0;
  for (size_t t = 0; t < mesh.TriangleCount(); ++t) {
    const Eigen::Vector3d p0 = mesh.positions[mesh.indices[3 * t]].cast<double>() - c;
    const Eigen::Vector3d p1 = mesh.positions[mesh.indices[3 * t + 1]].cast<double>() - c;
    const Eigen::Vector3d p2 = mesh.positions[mesh.indices[3 * t + 2]].cast<double>() - c;
    v += p0.dot(p1.cross(p2));
  }
  return v / 6;
}

}  // namespace lt

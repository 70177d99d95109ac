// An independent reference for the ground-truth stripe centres of a triangle
// mesh scene, sharing no code with render/stripe_truth: the stripe is the set of
// segments where each sheet's plane cuts each triangle (exact, per triangle, in
// double); each segment is projected through the camera model (Camera::Project,
// with its distortion) and, for every image row, the points where the projected
// segment crosses the row (or column) are found by bisection on the segment's
// parameter (distortion bends the projected segment). A crossing is kept when its point is
// the first surface seen from the camera (nothing on the segment camera -> point),
// faces camera and projector alike and nothing lies on the segment point ->
// projector, and lies inside the fan (the sheet's intensity there at least 1% of
// its central ray's at the same distance, as StripeTruthOptions' default); the
// occlusion tests are brute force over every triangle, not Embree's.
//
// Decisions the reference cannot make to the tolerance are "ambiguous" and left
// out of the comparison (counted): an occluder whose edge passes within kMarginM
// of a segment, a fan edge within kMarginM, a surface met within kMarginM of the point (a crease), a point
// within 1e-3 px of the image border, two crossings of one sheet closer than
// that on one row.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <vector>

#include "render/stripe_truth.h"
#include "render_test_world.h"

namespace lt::test {

struct RefTriangle {
  Eigen::Vector3d p[3];  // world frame
  Eigen::Vector3d n;     // unit, (p1 - p0) x (p2 - p0)
};

// Every triangle of the world's instances, vertices as the meshes hold them (float).
inline std::vector<RefTriangle> WorldTriangles(const World& world) {
  std::vector<RefTriangle> out;
  for (const SceneInstance& inst : world.geometry->instances) {
    const Mesh& m = world.geometry->meshes[inst.mesh];
    for (size_t t = 0; t < m.TriangleCount(); ++t) {
      RefTriangle tri;
      for (int k = 0; k < 3; ++k) tri.p[k] = inst.world_from_mesh * m.positions[m.indices[3 * t + size_t(k)]].cast<double>();
      tri.n = (tri.p[1] - tri.p[0]).cross(tri.p[2] - tri.p[0]).normalized();
      out.push_back(tri);
    }
  }
  return out;
}

enum class Blocked { kNo, kYes, kAmbiguous };

// Half of the decision band (metres): 1.5e-3 px at 0.1 m for a 150 px focal length.
constexpr double kMarginM = 1e-6;

// Whether a triangle lies on the open segment from x (on a surface) to e.
inline Blocked SegmentBlocked(const std::vector<RefTriangle>& tris, const Eigen::Vector3d& x, const Eigen::Vector3d& e) {
  const Eigen::Vector3d d = e - x;
  const double len = d.norm();
  bool ambiguous = false;
  for (const RefTriangle& tri : tris) {
    const double denom = tri.n.dot(d);
    if (denom == 0.0) continue;
    const double t = tri.n.dot(tri.p[0] - x) / denom;
    const double from_x = t * len;
    if (from_x < 1e-9 || t >= 1.0) continue;  // its own surface (x lies on it), or beyond e
    const Eigen::Vector3d h = x + t * d;
    // Signed distance of h from the triangle's edges (positive inside).
    double inside = 1e300;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = tri.p[k], b = tri.p[(k + 1) % 3];
      inside = std::min(inside, (b - a).cross(h - a).dot(tri.n) / (b - a).norm());
    }
    if (inside < -kMarginM) continue;
    if (from_x < kMarginM || inside <= kMarginM) {
      ambiguous = true;
      continue;
    }
    return Blocked::kYes;
  }
  return ambiguous ? Blocked::kAmbiguous : Blocked::kNo;
}

struct RefCrossing {
  double u = 0;
  bool ambiguous = false;
  Eigen::Vector3d p_world;
};

// (row, plane) -> crossings, for a single-laser or multi-laser rig.
using RefStripe = std::map<std::pair<int, int>, std::vector<RefCrossing>>;

// Reference crossings left out, by reason (each crossing counted once, first reason).
struct RefDropped {
  int facing = 0;  // the surface faces away from the camera or the projector
  int fan = 0;     // outside the fan
  int hidden = 0;  // another surface lies before it from the camera
  int shadow = 0;  // another surface lies between it and the projector
};

// The crossings of every image row (ScanAxis::kRows: RefCrossing::u is the
// column) or column (kCols: u is the row); keys (row or column, plane).
inline RefStripe ReferenceStripe(const World& world, const Camera& cam, const std::vector<LaserProjector>& lasers,
                                 const Pose& world_from_cam, RefDropped* dropped = nullptr,
                                 ScanAxis axis = ScanAxis::kRows) {
  const int line_index = axis == ScanAxis::kRows ? 1 : 0;  // pixel coordinate fixed along a scan line
  const int lines = axis == ScanAxis::kRows ? cam.height() : cam.width();
  const int length = axis == ScanAxis::kRows ? cam.width() : cam.height();
  RefDropped ignored;
  RefDropped& drop = dropped ? *dropped : ignored;
  const std::vector<RefTriangle> tris = WorldTriangles(world);
  const Pose cam_from_world = world_from_cam.inverse();
  const Eigen::Vector3d cam_o = world_from_cam.translation();
  RefStripe out;
  for (size_t l = 0; l < lasers.size(); ++l) {
    const LaserProjector& laser = lasers[l];
    const Eigen::Vector3d laser_o = world_from_cam * laser.origin_in_cam();
    const Pose projector_from_world = laser.projector_from_cam() * cam_from_world;
    for (int s = 0; s < laser.sheet_count(); ++s) {
      auto in_fan = [&](const Eigen::Vector3d& x) {
        const Eigen::Vector3d p = projector_from_world * x;
        return laser.SheetIntensityAt(s, p) >= 0.01 * laser.SheetIntensityAt(s, laser.SheetDirection(s) * p.norm());
      };
      const int plane = GlobalPlaneIndex(lasers, int(l), s);
      const Plane sheet = lasers[l].SheetPlane(s).Transformed(world_from_cam);
      for (const RefTriangle& tri : tris) {
        double g[3];
        for (int k = 0; k < 3; ++k) g[k] = sheet.SignedDistance(tri.p[k]);
        std::vector<Eigen::Vector3d> ends;
        for (int k = 0; k < 3; ++k) {
          const double ga = g[k], gb = g[(k + 1) % 3];
          if (ga == 0.0) ends.push_back(tri.p[k]);
          if ((ga < 0 && gb > 0) || (ga > 0 && gb < 0)) {
            ends.push_back(tri.p[k] + ga / (ga - gb) * (tri.p[(k + 1) % 3] - tri.p[k]));
          }
        }
        if (ends.size() != 2) continue;  // misses, touches at a vertex, or lies in the sheet
        const Eigen::Vector3d a = ends[0], b = ends[1];
        auto row_of = [&](double t) -> std::optional<double> {
          auto px = cam.Project(cam_from_world * (a + t * (b - a)));
          if (!px) return std::nullopt;
          return (*px)[line_index];
        };
        const int pieces = 16;
        for (int i = 0; i < pieces; ++i) {
          const double t0 = double(i) / pieces, t1 = double(i + 1) / pieces;
          auto v0 = row_of(t0), v1 = row_of(t1);
          if (!v0 || !v1) continue;
          const double lo = std::min(*v0, *v1), hi = std::max(*v0, *v1);
          for (int row = std::max(0, int(std::ceil(lo))); row <= std::min(lines - 1, int(std::floor(hi)));
               ++row) {
            if (row == hi && hi != lo) continue;  // half-open: a shared end belongs to one piece
            double ta = t0, tb = t1, fa = *v0 - row;
            for (int it = 0; it < 80; ++it) {
              const double tm = 0.5 * (ta + tb);
              auto vm = row_of(tm);
              if (!vm) break;
              if ((*vm - row > 0) == (fa > 0)) {
                ta = tm, fa = *vm - row;
              } else {
                tb = tm;
              }
            }
            const Eigen::Vector3d x = a + 0.5 * (ta + tb) * (b - a);
            auto px = cam.Project(cam_from_world * x);
            if (!px) continue;
            RefCrossing c;
            c.u = (*px)[1 - line_index];
            c.p_world = x;
            // Duplicates: a crossing at an edge shared by two triangles.
            auto& list = out[{row, plane}];
            bool seen = false;
            for (const RefCrossing& o : list) seen = seen || (o.p_world - x).norm() < 1e-9;
            if (seen) continue;
            if (c.u < -0.5 - 1e-3 || c.u > length - 0.5 + 1e-3) continue;
            c.ambiguous = c.u < -0.5 + 1e-3 || c.u > length - 0.5 - 1e-3;
            const double fc = tri.n.dot((cam_o - x).normalized()), fl = tri.n.dot((laser_o - x).normalized());
            if (fc == 0.0 || fl == 0.0 || (fc > 0) != (fl > 0)) {
              ++drop.facing;
              continue;
            }
            const Eigen::Vector3d along = kMarginM * (b - a).normalized();
            const bool fan = in_fan(x);
            if (!fan && !in_fan(x + along) && !in_fan(x - along)) {
              ++drop.fan;
              continue;
            }
            c.ambiguous = c.ambiguous || !fan || !in_fan(x + along) || !in_fan(x - along);
            const Blocked seen_by_cam = SegmentBlocked(tris, x, cam_o);
            if (seen_by_cam == Blocked::kYes) {
              ++drop.hidden;
              continue;
            }
            const Blocked shadow = SegmentBlocked(tris, x, laser_o);
            if (shadow == Blocked::kYes) {
              ++drop.shadow;
              continue;
            }
            c.ambiguous = c.ambiguous || seen_by_cam == Blocked::kAmbiguous || shadow == Blocked::kAmbiguous;
            list.push_back(c);
          }
        }
      }
    }
  }
  // Two crossings of one sheet within the tolerance on one row cannot be told apart.
  for (auto& [key, list] : out) {
    for (size_t i = 0; i < list.size(); ++i) {
      for (size_t j = i + 1; j < list.size(); ++j) {
        if (std::abs(list[i].u - list[j].u) < 2e-3) list[i].ambiguous = list[j].ambiguous = true;
      }
    }
  }
  return out;
}

// The comparison of ComputeStripeCenters' centres with the reference.
struct RefComparison {
  int reference = 0;  // unambiguous reference crossings
  int ambiguous = 0;  // reference crossings left out
  int found = 0;      // reference crossings with a centre within the tolerance
  int missed = 0;
  int extra = 0;      // centres with no reference crossing (ambiguous or not) within the tolerance
  double max_du = 0;  // over the found ones
  std::vector<std::string> missed_where, extra_where;  // "line v plane p u ..." (first few)
  // Missed crossings that share the interval between two pixel centres with
  // another crossing of the same sheet on the same surface side (no sign change
  // of the signed distance between the centres).
  int missed_paired = 0;
  int rows_with_two = 0;  // (row, plane) with two or more unambiguous crossings
  RefDropped dropped;     // filled by the caller
};

inline RefComparison CompareWithReference(const RefStripe& ref, const std::vector<StripeCenter>& centers,
                                          double tol_px, ScanAxis axis = ScanAxis::kRows) {
  RefComparison r;
  std::map<std::pair<int, int>, std::vector<double>> got;
  for (const StripeCenter& c : centers) {
    if (axis == ScanAxis::kRows) {
      got[{int(std::lround(c.v)), c.plane}].push_back(c.u);
    } else {
      got[{int(std::lround(c.u)), c.plane}].push_back(c.v);
    }
  }
  for (const auto& [key, list] : ref) {
    const auto it = got.find(key);
    r.rows_with_two += std::count_if(list.begin(), list.end(), [](const RefCrossing& c) { return !c.ambiguous; }) >= 2;
    for (const RefCrossing& c : list) {
      if (c.ambiguous) {
        ++r.ambiguous;
        continue;
      }
      ++r.reference;
      double best = 1e300;
      if (it != got.end()) {
        for (double u : it->second) best = std::min(best, std::abs(u - c.u));
      }
      if (best <= tol_px) {
        ++r.found;
        r.max_du = std::max(r.max_du, best);
        continue;
      }
      ++r.missed;
      // A partner between the same two pixel centres (floor(u + 0) equal)?
      for (const RefCrossing& o : list) {
        if (&o != &c && std::floor(o.u) == std::floor(c.u)) {
          ++r.missed_paired;
          break;
        }
      }
      if (r.missed_where.size() < 8) {
        r.missed_where.push_back("line " + std::to_string(key.first) + " plane " + std::to_string(key.second) +
                                 " u " + std::to_string(c.u));
      }
    }
  }
  for (const auto& [key, list] : got) {
    const auto it = ref.find(key);
    for (double u : list) {
      double best = 1e300;
      if (it != ref.end()) {
        for (const RefCrossing& c : it->second) best = std::min(best, std::abs(u - c.u) - (c.ambiguous ? 1e-2 : 0.0));
      }
      if (best <= tol_px) continue;
      ++r.extra;
      if (r.extra_where.size() < 8) {
        r.extra_where.push_back("line " + std::to_string(key.first) + " plane " + std::to_string(key.second) +
                                " u " + std::to_string(u));
      }
    }
  }
  return r;
}

}  // namespace lt::test

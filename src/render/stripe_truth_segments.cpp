#include "render/stripe_truth_segments.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>
#include <cmath>
#include <tuple>

namespace lt::stripe_truth_detail {

namespace {

// Projected pieces of a segment longer than this (px) are split: the row of a
// distorted projection bends negligibly within one (a pinhole's is straight).
constexpr double kPiecePx = 2.0;
// Splits of a piece at most (toward the camera plane or the edge of the
// distortion's valid domain the projection grows without bound).
constexpr int kMaxDepth = 48;
// Splits of a piece with no end in the domain at most.
constexpr int kInvalidDepth = 6;
// The first bracket about a candidate (px either side) and the widest.
constexpr double kFirstBracketPx = 1e-5;
constexpr double kWidestBracketPx = 1e-2;

// Where a sheet cuts a triangle (world frame).
struct Segment {
  Eigen::Vector3d a, b, normal;  // normal: unit, (p1 - p0) x (p2 - p0)
  int sheet;                     // index into the sheets
  uint32_t instance, primitive;
};

// A segment's crossing of a scan line.
struct Candidate {
  int sheet;
  double s;  // position along the line (px)
  uint32_t instance, primitive;
  Eigen::Vector3d x, normal;
  bool operator<(const Candidate& o) const {
    return std::tie(sheet, s, instance, primitive) < std::tie(o.sheet, o.s, o.instance, o.primitive);
  }
};

// The segments where every sheet cuts every triangle: the sheet's plane cuts
// the edges whose corners it separates (a corner on it is an end itself); a
// triangle touching it at one corner, or lying in it, gives none.
std::vector<Segment> SheetSegments(const SceneGeometry& geometry, const std::vector<WorldSheet>& sheets) {
  tbb::enumerable_thread_specific<std::vector<Segment>> local;
  // Each mesh's bounds, once however often it is instanced: an instance whose box no
  // sheet cuts is skipped whole.
  std::vector<std::optional<Eigen::AlignedBox3d>> mesh_bounds(geometry.meshes.size());
  for (size_t i = 0; i < geometry.instances.size(); ++i) {
    const SceneInstance& inst = geometry.instances[i];
    const Mesh& mesh = geometry.meshes[inst.mesh];
    // The sheets' planes in the mesh frame, to skip the triangles wholly on one
    // side with a margin far above the rounding of either frame.
    std::vector<Eigen::Vector4d> in_mesh;
    for (const WorldSheet& ws : sheets) {
      const Eigen::Vector3d n = inst.world_from_mesh.linear().transpose() * ws.plane_world.n;
      in_mesh.emplace_back(n.x(), n.y(), n.z(), ws.plane_world.SignedDistance(inst.world_from_mesh.translation()));
    }
    std::optional<Eigen::AlignedBox3d>& box = mesh_bounds[inst.mesh];
    if (!box) box = mesh.Bounds();
    if (box->isEmpty()) continue;
    // The same test as each triangle's below, over the box: its slack is at least any
    // triangle's, so a box wholly on one side of every sheet holds no segment.
    const double box_size = std::max(box->min().cwiseAbs().maxCoeff(), box->max().cwiseAbs().maxCoeff());
    const Eigen::Vector3d centre = box->center(), half = 0.5 * box->sizes();
    const bool cut = std::any_of(in_mesh.begin(), in_mesh.end(), [&](const Eigen::Vector4d& pl) {
      const Eigen::Vector3d n = pl.head<3>();
      const double slack = 1e-9 * (std::abs(pl.w()) + n.lpNorm<1>() * box_size) + 1e-300;
      const double g = n.dot(centre) + pl.w(), reach = n.cwiseAbs().dot(half);
      return g - reach <= slack && g + reach >= -slack;
    });
    if (!cut) continue;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.TriangleCount(), 2048), [&](const auto& range) {
      std::vector<Segment>& out = local.local();
      for (size_t t = range.begin(); t != range.end(); ++t) {
        Eigen::Vector3d p[3];
        for (int k = 0; k < 3; ++k) p[k] = mesh.positions[mesh.indices[3 * t + size_t(k)]].cast<double>();
        const double size = std::max({p[0].cwiseAbs().maxCoeff(), p[1].cwiseAbs().maxCoeff(), p[2].cwiseAbs().maxCoeff()});
        bool world_known = false;
        Eigen::Vector3d w[3];
        for (size_t s = 0; s < sheets.size(); ++s) {
          const Eigen::Vector4d& pl = in_mesh[s];
          const Eigen::Vector3d n = pl.head<3>();
          const double slack = 1e-9 * (std::abs(pl.w()) + n.lpNorm<1>() * size) + 1e-300;
          const double g0 = n.dot(p[0]) + pl.w(), g1 = n.dot(p[1]) + pl.w(), g2 = n.dot(p[2]) + pl.w();
          if (std::min({g0, g1, g2}) > slack || std::max({g0, g1, g2}) < -slack) continue;
          if (!world_known) {
            for (int k = 0; k < 3; ++k) w[k] = inst.world_from_mesh * p[k];
            world_known = true;
          }
          const Plane& plane = sheets[s].plane_world;
          double g[3];
          for (int k = 0; k < 3; ++k) g[k] = plane.SignedDistance(w[k]);
          Eigen::Vector3d ends[3];
          int count = 0;
          for (int k = 0; k < 3 && count < 3; ++k) {
            const double ga = g[k], gb = g[(k + 1) % 3];
            if (ga == 0.0) ends[count++] = w[k];
            if (count < 3 && ((ga < 0 && gb > 0) || (ga > 0 && gb < 0))) {
              ends[count++] = w[k] + ga / (ga - gb) * (w[(k + 1) % 3] - w[k]);
            }
          }
          if (count != 2) continue;
          const Eigen::Vector3d normal = (w[1] - w[0]).cross(w[2] - w[0]);
          if (!(normal.norm() > 0)) continue;
          out.push_back({ends[0], ends[1], normal.normalized(), int(s), uint32_t(i), uint32_t(t)});
        }
      }
    });
  }
  std::vector<Segment> all;
  for (auto& v : local) all.insert(all.end(), v.begin(), v.end());
  return all;
}

// The crossings of a segment's projection with the scan lines, added to
// by_line[line]. The projection is split into pieces of at most kPiecePx;
// pieces wholly outside the image are dropped.
void Crossings(const Segment& seg, const Camera& camera, const Pose& cam_from_world, ScanAxis axis,
               std::vector<std::vector<Candidate>>& by_line) {
  const int li = axis == ScanAxis::kRows ? 1 : 0;  // the pixel coordinate fixed along a line
  const int lines = axis == ScanAxis::kRows ? camera.height() : camera.width();
  const int length = axis == ScanAxis::kRows ? camera.width() : camera.height();
  const Eigen::Vector3d a = cam_from_world * seg.a, d = cam_from_world.linear() * (seg.b - seg.a);
  // Wholly behind a pinhole-model camera.
  if (camera.params().distortion != DistortionModel::kFisheye && a.z() <= 0 && a.z() + d.z() <= 0) return;
  auto project = [&](double t) { return camera.Project(a + t * d); };
  struct Piece {
    double t0, t1;
    std::optional<Eigen::Vector2d> p0, p1;
    int depth;
  };
  std::vector<Piece> stack = {{0.0, 1.0, project(0.0), project(1.0), 0}};
  const double w = camera.width() - 0.5, h = camera.height() - 0.5;
  while (!stack.empty()) {
    const Piece pc = stack.back();
    stack.pop_back();
    auto split = [&] {
      if (pc.depth >= kMaxDepth) return;
      const double tm = 0.5 * (pc.t0 + pc.t1);
      const auto pm = project(tm);
      stack.push_back({tm, pc.t1, pm, pc.p1, pc.depth + 1});
      stack.push_back({pc.t0, tm, pc.p0, pm, pc.depth + 1});
    };
    if (!pc.p0 || !pc.p1) {
      // Toward the edge of the valid domain: split down to kMaxDepth; a piece
      // with no valid end may still pass through the domain (Brown-Conrady's
      // is star-shaped about the axis): looked at on 2^kInvalidDepth pieces.
      if (pc.p0 || pc.p1 || pc.depth < kInvalidDepth) split();
      continue;
    }
    const Eigen::Vector2d &p0 = *pc.p0, &p1 = *pc.p1;
    const double tm = 0.5 * (pc.t0 + pc.t1);
    const auto pm = project(tm);
    if (!pm) {
      split();
      continue;
    }
    // Dropped when wholly beyond one side of the image by more than its bend
    // (a pinhole's projection is straight; the midpoint's distance off the
    // chord, four times over, bounds a distorted one's at this scale).
    const Eigen::Vector2d chord = p1 - p0, to_m = *pm - p0;
    const double off = chord.norm() > 0 ? std::abs(chord.x() * to_m.y() - chord.y() * to_m.x()) / chord.norm()
                                        : to_m.norm();
    const double m = 1 + 4 * off;
    auto beyond = [&](int axis_i, double edge, double sign) {
      return sign * (p0[axis_i] - edge) > m && sign * (p1[axis_i] - edge) > m && sign * ((*pm)[axis_i] - edge) > m;
    };
    if (beyond(0, -0.5, -1) || beyond(0, w, +1) || beyond(1, -0.5, -1) || beyond(1, h, +1)) continue;
    if (chord.norm() > kPiecePx && pc.depth < kMaxDepth) {
      stack.push_back({tm, pc.t1, pm, pc.p1, pc.depth + 1});
      stack.push_back({pc.t0, tm, pc.p0, pm, pc.depth + 1});
      continue;
    }
    const double f0 = p0[li], f1 = p1[li];
    const int lo = std::max(0, int(std::ceil(std::min(f0, f1)))), hi = std::min(lines - 1, int(std::floor(std::max(f0, f1))));
    for (int line = lo; line <= hi; ++line) {
      // Illinois on the line coordinate along the segment's parameter.
      double ta = pc.t0, tb = pc.t1, fa = f0 - line, fb = f1 - line;
      double t = fa == 0.0 ? ta : tb;
      if (fa != 0.0 && fb != 0.0) {
        int side = 0;
        for (int it = 0; it < 100; ++it) {
          t = (ta * fb - tb * fa) / (fb - fa);
          if (!(t > std::min(ta, tb) && t < std::max(ta, tb))) t = 0.5 * (ta + tb);
          const auto pt = project(t);
          if (!pt) break;
          const double ft = (*pt)[li] - line;
          if (std::abs(ft) <= 1e-13 * (1 + line) || t == ta || t == tb) break;
          if ((ft > 0) == (fb > 0)) {
            tb = t, fb = ft;
            if (side == -1) fa *= 0.5;
            side = -1;
          } else {
            ta = t, fa = ft;
            if (side == +1) fb *= 0.5;
            side = +1;
          }
        }
      }
      const auto px = project(t);
      if (!px) continue;
      const double s = (*px)[1 - li];
      if (!(s >= -0.5 && s <= length - 0.5)) continue;
      by_line[size_t(line)].push_back({seg.sheet, s, seg.instance, seg.primitive, seg.a + t * (seg.b - seg.a), seg.normal});
    }
  }
}

// Whether `centres` holds one of `plane` within kKnownPx of s along the line.
bool Known(const std::vector<StripeCenter>& centres, int plane, double s, ScanAxis axis) {
  for (const StripeCenter& c : centres) {
    if (c.plane == plane && std::abs((axis == ScanAxis::kRows ? c.u : c.v) - s) <= kKnownPx) return true;
  }
  return false;
}

}  // namespace

void AddCentresFromSegments(const EmbreeScene& scene, const Camera& camera, const std::vector<WorldSheet>& sheets,
                            const LineScanner& scanner, const Pose& world_from_cam, ScanAxis axis,
                            std::vector<std::vector<StripeCenter>>& per_line) {
  const Pose cam_from_world = world_from_cam.inverse();
  const std::vector<Segment> segments = SheetSegments(scene.geometry(), sheets);
  const size_t lines = per_line.size();
  tbb::enumerable_thread_specific<std::vector<std::vector<Candidate>>> local(
      [&] { return std::vector<std::vector<Candidate>>(lines); });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, segments.size(), 64), [&](const auto& range) {
    auto& by_line = local.local();
    for (size_t i = range.begin(); i != range.end(); ++i) Crossings(segments[i], camera, cam_from_world, axis, by_line);
  });
  std::vector<std::vector<Candidate>> by_line(lines);
  for (auto& part : local) {
    for (size_t l = 0; l < lines; ++l) by_line[l].insert(by_line[l].end(), part[l].begin(), part[l].end());
  }
  const Eigen::Vector3d cam_o = world_from_cam.translation();
  tbb::parallel_for(size_t(0), lines, [&](size_t l) {
    std::vector<Candidate>& cands = by_line[l];
    if (cands.empty()) return;
    std::sort(cands.begin(), cands.end());
    const int line = int(l);
    std::vector<StripeCenter>& out = per_line[l];
    bool added = false;
    for (const Candidate& c : cands) {
      const WorldSheet& ws = sheets[size_t(c.sheet)];
      if (Known(out, ws.plane, c.s, axis)) continue;
      Sample probe;
      probe.valid = true;
      probe.p_world = c.x;
      probe.normal = c.normal;
      probe.depth = (c.x - cam_o).norm();
      if (!scanner.FacesAndInFan(ws, probe)) continue;
      // The first surface seen at s must be this point.
      Hit hit;
      const Sample seen = scanner.Cast(line, c.s, &hit);
      if (!seen.valid) continue;
      const bool same = (hit.instance_id == c.instance && hit.primitive_id == c.primitive) ||
                        (seen.p_world - c.x).norm() <= 1e-3 * scanner.Footprint(probe.depth);
      if (!same) continue;
      // A bracket about s on that surface, widened until the sheet's signed
      // distance changes sign across it.
      std::optional<std::pair<double, Sample>> root;
      for (double delta = kFirstBracketPx; delta <= kWidestBracketPx; delta *= 4) {
        const Sample lo = scanner.Cast(line, c.s - delta), hi = scanner.Cast(line, c.s + delta);
        if (!lo.valid || !hi.valid || !scanner.OnSurfaceOf(seen, lo) || !scanner.OnSurfaceOf(seen, hi)) break;
        const double glo = ws.plane_world.SignedDistance(lo.p_world), ghi = ws.plane_world.SignedDistance(hi.p_world);
        if (glo == 0.0 || ghi == 0.0 || (glo > 0) != (ghi > 0)) {
          root = scanner.Refine(line, ws, c.s - delta, lo, c.s + delta, hi);
          break;
        }
      }
      if (!root || Known(out, ws.plane, root->first, axis) || !scanner.Lit(ws, root->second)) continue;
      out.push_back(scanner.Centre(line, ws, *root));
      added = true;
    }
    if (added) {
      std::stable_sort(out.begin(), out.end(), [axis](const StripeCenter& a, const StripeCenter& b) {
        const double sa = axis == ScanAxis::kRows ? a.u : a.v, sb = axis == ScanAxis::kRows ? b.u : b.v;
        return a.plane != b.plane ? a.plane < b.plane : sa < sb;
      });
    }
  });
}

}  // namespace lt::stripe_truth_detail

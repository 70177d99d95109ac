// The ray-casting search along one scan line behind ComputeStripeCenters
// (render/stripe_truth.h): casts, root refinement, surface breaks and the lit
// test. Internal to render/stripe_truth*.cpp.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "core/pose.h"
#include "render/stripe_truth.h"
#include "scene/embree_scene.h"
#include "sensor/camera.h"
#include "sensor/laser.h"

namespace lt::stripe_truth_detail {

// One laser sheet in the world frame, with what the lit test needs.
struct WorldSheet {
  int plane;
  const LaserProjector* laser;
  int sheet;
  Plane plane_world;
  Eigen::Vector3d origin_world;
  Pose projector_from_world;
};

using Sample = ChiefHit;

// Surfaces whose normals differ by more than this meet at a crease: the line is
// searched on each up to the crease (a sheet may cross both within a pixel).
constexpr double kBreakDegrees = 30.0;
// A line crossing from one surface to another and on to a third within one
// pixel (a step's top, wall and floor) is split at up to this many breaks.
constexpr int kMaxBreaks = 3;
// A bracket this narrow (px) whose ends still lie on two surfaces apart holds
// a depth discontinuity, not a crossing: refining it on to tolerance_px only
// confirms that. A crossing it could still hold lies on a surface seen over
// less than this, or within it of a crease on a surface seen at more than 84
// degrees (ends 1e-3 footprints apart over 1e-4 px).
constexpr double kDiscontinuityPx = 1e-4;
// A bracket's ends whose normals differ by less than this lie on one plane
// where each is on the other's tangent plane.
constexpr double kSamePlaneDegrees = 1.0;
// Facets whose normals differ by more than this (radians) meet at a crease
// where the sheet may cross the surface twice between two samples.
constexpr double kCreaseRad = 1e-4;
// Casts spent per interval looking for such a pair of crossings.
constexpr int kPairCasts = 64;

class LineScanner {
 public:
  LineScanner(const EmbreeScene& scene, const Camera& camera, const Pose& world_from_cam, ScanAxis axis,
              const StripeTruthOptions& options)
      : scene_(scene),
        camera_(camera),
        world_from_cam_(world_from_cam),
        cam_from_world_(world_from_cam.inverse()),
        axis_(axis),
        options_(options) {}

  // Pixel of position s along scan line `line`.
  Eigen::Vector2d Pixel(int line, double s) const {
    return axis_ == ScanAxis::kRows ? Eigen::Vector2d(s, line) : Eigen::Vector2d(line, s);
  }

  // The centre a refined root (position along scan line `line`, surface point) gives.
  StripeCenter Centre(int line, const WorldSheet& ws, const std::pair<double, Sample>& root) const {
    const Eigen::Vector2d px = Pixel(line, root.first);
    StripeCenter c;
    c.u = px.x();
    c.v = px.y();
    c.plane = ws.plane;
    c.p_world = root.second.p_world;
    c.p_cam = cam_from_world_ * c.p_world;
    return c;
  }

  // The first hit of the chief ray at position s along scan line `line`;
  // `full` (optional) receives Embree's hit, when there is one.
  Sample Cast(int line, double s, Hit* full = nullptr) const {
    Sample out;
    auto dir = camera_.Unproject(Pixel(line, s));
    if (!dir) return out;
    Ray ray;
    ray.origin = world_from_cam_.translation();
    ray.direction = world_from_cam_.linear() * *dir;
    auto hit = scene_.Intersect(ray);
    if (!hit) return out;
    if (full) *full = *hit;
    out.valid = true;
    out.p_world = hit->position;
    out.normal = hit->geometric_normal;
    out.depth = hit->t * ray.direction.norm();
    return out;
  }

  // Footprint of one pixel at a distance (metres), for the continuity test.
  double Footprint(double depth) const { return depth * camera_.pixel_pitch_m() / camera_.image_distance_m(); }

  // Refines a sign change of the sheet's signed distance between s0 and s1.
  std::optional<std::pair<double, Sample>> Refine(int line, const WorldSheet& ws, double s0, Sample a, double s1,
                                                  Sample b) const {
    double g0 = ws.plane_world.SignedDistance(a.p_world), g1 = ws.plane_world.SignedDistance(b.p_world);
    if (g0 == 0.0) return std::make_pair(s0, a);
    if (g1 == 0.0) return std::make_pair(s1, b);
    int side = 0;
    for (int it = 0; it < options_.max_iterations && std::abs(s1 - s0) > options_.tolerance_px; ++it) {
      if (std::abs(s1 - s0) < kDiscontinuityPx && MayBreak(a, b) && Apart(a, b)) return std::nullopt;
      double s = (s0 * g1 - s1 * g0) / (g1 - g0);  // regula falsi
      double lo = std::min(s0, s1), hi = std::max(s0, s1), w = hi - lo;
      if (!(s > lo + 1e-3 * w && s < hi - 1e-3 * w)) s = 0.5 * (s0 + s1);
      Sample m = Cast(line, s);
      if (!m.valid) return std::nullopt;
      double gm = ws.plane_world.SignedDistance(m.p_world);
      if (gm == 0.0) return std::make_pair(s, m);
      if ((gm > 0) == (g1 > 0)) {
        s1 = s, b = m, g1 = gm;
        if (side == -1) g0 *= 0.5;  // Illinois: halve the stale end
        side = -1;
      } else {
        s0 = s, a = m, g0 = gm;
        if (side == +1) g1 *= 0.5;
        side = +1;
      }
    }
    // A crossing on a continuous surface: both ends converge onto one point.
    if (Apart(a, b)) return std::nullopt;
    const Sample& best = std::abs(ws.plane_world.SignedDistance(a.p_world)) <=
                                 std::abs(ws.plane_world.SignedDistance(b.p_world))
                             ? a
                             : b;
    double s_best = &best == &a ? s0 : s1;
    // Interpolate within the final bracket for the last digits.
    double ga = ws.plane_world.SignedDistance(a.p_world), gb = ws.plane_world.SignedDistance(b.p_world);
    double s = (ga != gb) ? (s0 * gb - s1 * ga) / (gb - ga) : s_best;
    if (!(s >= std::min(s0, s1) && s <= std::max(s0, s1))) s = s_best;
    return std::make_pair(s, best);
  }

  // Whether a bracket's ends are more than 1e-3 of a pixel's footprint apart
  // and not on one plane (normals within kSamePlaneDegrees, each end within
  // that distance of the other's tangent plane): a surface seen edge-on spans
  // more than that over a 1e-6 px bracket.
  bool Apart(const Sample& a, const Sample& b) const {
    static const double kCosSamePlane = std::cos(kSamePlaneDegrees * M_PI / 180.0);
    const double tol = 1e-3 * Footprint(std::max(a.depth, b.depth));
    const Eigen::Vector3d ab = b.p_world - a.p_world;
    if (ab.norm() <= tol) return false;
    return !(std::abs(a.normal.dot(b.normal)) >= kCosSamePlane && std::abs(a.normal.dot(ab)) <= tol &&
             std::abs(b.normal.dot(ab)) <= tol);
  }

  // Whether neighbouring samples may lie on two surfaces: one a hit and the
  // other not, normals more than kBreakDegrees apart (a crease), or one off
  // the other's plane by more than a pixel's footprint (a step).
  bool MayBreak(const Sample& a, const Sample& b) const { return !OnSurfaceOf(a, b) || !OnSurfaceOf(b, a); }

  // Whether m lies on the surface of a: both hits (or both misses), normals
  // within kBreakDegrees, m within a pixel's footprint of a's plane.
  bool OnSurfaceOf(const Sample& a, const Sample& m) const {
    static const double kCosBreak = std::cos(kBreakDegrees * M_PI / 180.0);
    if (a.valid != m.valid) return false;
    if (!a.valid) return true;
    return std::abs(a.normal.dot(m.normal)) >= kCosBreak &&
           std::abs(a.normal.dot(m.p_world - a.p_world)) <= Footprint(std::max(a.depth, m.depth));
  }

  // Where the line leaves the surface of a between s0 (sample a) and s1 (b):
  // the last sample on it and the first beyond, tolerance_px apart.
  struct Break {
    double s_a;
    Sample a;
    double s_b;
    Sample b;
  };
  Break FindBreak(int line, double s0, const Sample& a, double s1, Sample b) const {
    double lo = s0;
    Sample on = a;
    for (int it = 0; it < options_.max_iterations && std::abs(s1 - lo) > options_.tolerance_px; ++it) {
      const double s = 0.5 * (lo + s1);
      Sample m = Cast(line, s);
      if (OnSurfaceOf(a, m)) {
        lo = s, on = m;
      } else {
        s1 = s, b = m;
      }
    }
    return Break{lo, on, s1, b};
  }

  // Between samples a (at s0) and b (at s1) on one surface, with the sheet's
  // signed distance of one sign at both, the sheet may still cross the surface
  // twice: where the stripe turns back across the scan line (the top of an
  // arc) or crosses two facets on either side of a crease. On a facet the
  // distance is monotonic along the line (a ratio of linear functions for a
  // pinhole; distortion bends it negligibly within a pixel), so such a pair
  // straddles a crease: the interval is bisected toward every crease (normals
  // apart) until a sample lies between the pair, down to kDiscontinuityPx
  // (a pair closer than that is a tangency). Returns the two brackets of the
  // pair (sign changes) when found.
  struct Bracket {
    double s0;
    Sample a;
    double s1;
    Sample b;
  };
  bool FindPair(int line, const WorldSheet& ws, double s0, const Sample& a, double s1, const Sample& b, int& budget,
                std::vector<Bracket>& out) const {
    static const double kCosCrease = std::cos(kCreaseRad);
    if (budget <= 0 || std::abs(s1 - s0) <= kDiscontinuityPx || a.normal.dot(b.normal) >= kCosCrease) return false;
    const double s = 0.5 * (s0 + s1);
    const Sample m = Cast(line, s);
    --budget;
    if (!m.valid || !OnSurfaceOf(a, m) || !OnSurfaceOf(b, m)) return false;
    const double ga = ws.plane_world.SignedDistance(a.p_world), gm = ws.plane_world.SignedDistance(m.p_world);
    if (gm == 0.0 || (gm > 0) != (ga > 0)) {
      out.push_back({s0, a, s, m});
      out.push_back({s, m, s1, b});
      return true;
    }
    return FindPair(line, ws, s0, a, s, m, budget, out) || FindPair(line, ws, s, m, s1, b, budget, out);
  }

  // Whether p faces the camera and the projector alike and lies in the fan:
  // the fan profile there is at least `fan_threshold` of its value on the
  // sheet's central ray at the same distance. No ray is cast.
  bool FacesAndInFan(const WorldSheet& ws, const Sample& p) const {
    Eigen::Vector3d to_cam = world_from_cam_.translation() - p.p_world;
    Eigen::Vector3d to_laser = ws.origin_world - p.p_world;
    double facing_cam = p.normal.dot(to_cam), facing_laser = p.normal.dot(to_laser);
    if (facing_cam == 0.0 || facing_laser == 0.0 || (facing_cam > 0) != (facing_laser > 0)) return false;
    // Fan: relative to the central ray at the same distance.
    Eigen::Vector3d p_proj = ws.projector_from_world * p.p_world;
    double r = p_proj.norm();
    double here = ws.laser->SheetIntensityAt(ws.sheet, p_proj);
    double central = ws.laser->SheetIntensityAt(ws.sheet, ws.laser->SheetDirection(ws.sheet) * r);
    return central > 0 && !(here < options_.fan_threshold * central);
  }

  // Whether nothing lies between p and the projector.
  bool Unshadowed(const WorldSheet& ws, const Sample& p) const {
    const double facing_laser = p.normal.dot(ws.origin_world - p.p_world);
    // Shadow: offset the start along the normal, toward the laser's side, by
    // the float precision of the render frame (Embree's coordinates), not of
    // the world: 1 km from the world origin a world-scaled offset is 1 mm and
    // starts inside a narrow slot's other wall.
    double scale = std::max({1.0, scene_.RenderFromWorld(p.p_world).cwiseAbs().maxCoeff()});
    double eps = 1e-6 * scale + 1e-4 * Footprint(p.depth);
    Eigen::Vector3d n = facing_laser > 0 ? p.normal : Eigen::Vector3d(-p.normal);
    Ray shadow;
    shadow.origin = p.p_world + eps * n;
    shadow.direction = ws.origin_world - shadow.origin;
    shadow.t_min = 0;
    shadow.t_max = 1.0 - 1e-9;
    return !scene_.Occluded(shadow);
  }

  // A root counts as lit when both hold.
  bool Lit(const WorldSheet& ws, const Sample& p) const { return FacesAndInFan(ws, p) && Unshadowed(ws, p); }

 private:
  const EmbreeScene& scene_;
  const Camera& camera_;
  Pose world_from_cam_;
  Pose cam_from_world_;
  ScanAxis axis_;
  StripeTruthOptions options_;
};

}  // namespace lt::stripe_truth_detail

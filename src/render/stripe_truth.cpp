#include "render/stripe_truth.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace lt {

namespace {

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
      : scene_(scene), camera_(camera), world_from_cam_(world_from_cam), axis_(axis), options_(options) {}

  // Pixel of position s along scan line `line`.
  Eigen::Vector2d Pixel(int line, double s) const {
    return axis_ == ScanAxis::kRows ? Eigen::Vector2d(s, line) : Eigen::Vector2d(line, s);
  }

  Sample Cast(int line, double s) const {
    Sample out;
    auto dir = camera_.Unproject(Pixel(line, s));
    if (!dir) return out;
    Ray ray;
    ray.origin = world_from_cam_.translation();
    ray.direction = world_from_cam_.linear() * *dir;
    auto hit = scene_.Intersect(ray);
    if (!hit) return out;
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

  bool Lit(const WorldSheet& ws, const Sample& p) const {
    Eigen::Vector3d to_cam = world_from_cam_.translation() - p.p_world;
    Eigen::Vector3d to_laser = ws.origin_world - p.p_world;
    double facing_cam = p.normal.dot(to_cam), facing_laser = p.normal.dot(to_laser);
    if (facing_cam == 0.0 || facing_laser == 0.0 || (facing_cam > 0) != (facing_laser > 0)) return false;
    // Fan: relative to the central ray at the same distance.
    Eigen::Vector3d p_proj = ws.projector_from_world * p.p_world;
    double r = p_proj.norm();
    double here = ws.laser->SheetIntensityAt(ws.sheet, p_proj);
    double central = ws.laser->SheetIntensityAt(ws.sheet, ws.laser->SheetDirection(ws.sheet) * r);
    if (!(central > 0) || here < options_.fan_threshold * central) return false;
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

 private:
  const EmbreeScene& scene_;
  const Camera& camera_;
  Pose world_from_cam_;
  ScanAxis axis_;
  StripeTruthOptions options_;
};

}  // namespace

std::string ScanAxisName(ScanAxis axis) { return axis == ScanAxis::kRows ? "rows" : "cols"; }

void StripeTruthOptions::Check() const {
  if (!(tolerance_px > 0 && tolerance_px < 0.1)) throw std::invalid_argument("tolerance_px must be in (0, 0.1)");
  if (!(fan_threshold >= 0 && fan_threshold < 1)) throw std::invalid_argument("fan_threshold must be in [0, 1)");
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be >= 1");
}

ScanAxis ChooseScanAxis(const std::vector<LaserProjector>& lasers) {
  if (lasers.empty() || lasers[0].sheet_count() == 0) return ScanAxis::kRows;
  Eigen::Vector3d n = lasers[0].SheetPlane(0).n;
  return std::abs(n.x()) >= std::abs(n.y()) ? ScanAxis::kRows : ScanAxis::kCols;
}

int GlobalPlaneIndex(const std::vector<LaserProjector>& lasers, int laser, int sheet) {
  int index = 0;
  for (int i = 0; i < laser; ++i) index += lasers[size_t(i)].sheet_count();
  return index + sheet;
}

int PlaneCount(const std::vector<LaserProjector>& lasers) {
  return GlobalPlaneIndex(lasers, int(lasers.size()), 0);
}

std::vector<StripeCenter> ComputeStripeCenters(const EmbreeScene& scene, const Camera& camera,
                                               const std::vector<LaserProjector>& lasers,
                                               const Pose& world_from_cam, ScanAxis axis,
                                               const StripeTruthOptions& options,
                                               const std::vector<ChiefHit>* pixel_hits) {
  options.Check();
  if (pixel_hits && pixel_hits->size() != size_t(camera.width()) * size_t(camera.height())) {
    throw std::invalid_argument("pixel_hits must hold one hit per pixel");
  }
  std::vector<WorldSheet> sheets;
  for (size_t l = 0; l < lasers.size(); ++l) {
    const LaserProjector& laser = lasers[l];
    Pose world_from_projector = world_from_cam * laser.cam_from_projector();
    for (int s = 0; s < laser.sheet_count(); ++s) {
      sheets.push_back({GlobalPlaneIndex(lasers, int(l), s), &laser, s,
                        laser.SheetPlaneInProjector(s).Transformed(world_from_projector),
                        world_from_projector.translation(), world_from_projector.inverse()});
    }
  }
  const int lines = axis == ScanAxis::kRows ? camera.height() : camera.width();
  const int length = axis == ScanAxis::kRows ? camera.width() : camera.height();
  LineScanner scanner(scene, camera, world_from_cam, axis, options);
  Pose cam_from_world = world_from_cam.inverse();

  std::vector<std::vector<StripeCenter>> per_line(static_cast<size_t>(lines));
  tbb::parallel_for(0, lines, [&](int line) {
    // Samples at the image border (-0.5), every pixel centre, and the far border.
    std::vector<double> pos;
    pos.reserve(size_t(length) + 2);
    pos.push_back(-0.5);
    for (int i = 0; i < length; ++i) pos.push_back(i);
    pos.push_back(length - 0.5);
    std::vector<Sample> samples(pos.size());
    for (size_t i = 0; i < pos.size(); ++i) {
      bool centre = i > 0 && i + 1 < pos.size();
      if (pixel_hits && centre) {
        int along = int(i) - 1;
        size_t index = axis == ScanAxis::kRows ? size_t(line) * size_t(camera.width()) + size_t(along)
                                               : size_t(along) * size_t(camera.width()) + size_t(line);
        samples[i] = (*pixel_hits)[index];
      } else {
        samples[i] = scanner.Cast(line, pos[i]);
      }
    }
    auto& out = per_line[size_t(line)];
    // The surfaces between neighbouring samples, found once for all sheets:
    // pieces[i] holds the breaks between samples i and i + 1.
    std::map<size_t, std::vector<LineScanner::Break>> pieces;
    auto breaks_at = [&](size_t i) -> const std::vector<LineScanner::Break>& {
      auto it = pieces.find(i);
      if (it != pieces.end()) return it->second;
      std::vector<LineScanner::Break> breaks;
      double s = pos[i];
      Sample from = samples[i];
      while (int(breaks.size()) < kMaxBreaks && scanner.MayBreak(from, samples[i + 1])) {
        breaks.push_back(scanner.FindBreak(line, s, from, pos[i + 1], samples[i + 1]));
        s = breaks.back().s_b, from = breaks.back().b;
      }
      return pieces.emplace(i, std::move(breaks)).first->second;
    };
    for (const WorldSheet& ws : sheets) {
      // Whether the sheet may cross x's surface within what one pixel sees there.
      auto within_a_pixel = [&](const Sample& x) {
        if (!x.valid) return false;
        const Eigen::Vector3d view = (x.p_world - world_from_cam.translation()).normalized();
        const double cos_view = std::max(std::abs(x.normal.dot(view)), 0.05);
        return std::abs(ws.plane_world.SignedDistance(x.p_world)) < 2 * scanner.Footprint(x.depth) / cos_view;
      };
      // The crossing between samples a (at s0) and b (at s1) of one surface, if
      // any; with no sign change between them, near the sheet, the pair of
      // crossings that may lie between them.
      std::function<void(double, const Sample&, double, const Sample&)> add_root = [&](double s0, const Sample& a,
                                                                                      double s1, const Sample& b) {
        if (!a.valid || !b.valid) return;
        double ga = ws.plane_world.SignedDistance(a.p_world), gb = ws.plane_world.SignedDistance(b.p_world);
        // A root exactly on a sample belongs to the interval that starts there.
        bool crossing = (ga > 0 && gb < 0) || (ga < 0 && gb > 0) || ga == 0.0;
        if (!crossing) {
          std::vector<LineScanner::Bracket> pair;
          int budget = kPairCasts;
          if (gb != 0.0 && (within_a_pixel(a) || within_a_pixel(b)) &&
              scanner.FindPair(line, ws, s0, a, s1, b, budget, pair)) {
            for (const LineScanner::Bracket& br : pair) add_root(br.s0, br.a, br.s1, br.b);
          }
          return;
        }
        auto root = scanner.Refine(line, ws, s0, a, s1, b);
        if (!root || !scanner.Lit(ws, root->second)) return;
        Eigen::Vector2d px = scanner.Pixel(line, root->first);
        StripeCenter c;
        c.u = px.x();
        c.v = px.y();
        c.plane = ws.plane;
        c.p_world = root->second.p_world;
        c.p_cam = cam_from_world * c.p_world;
        out.push_back(c);
      };
      for (size_t i = 0; i + 1 < pos.size(); ++i) {
        const Sample &a = samples[i], &b = samples[i + 1];
        if (!a.valid && !b.valid) continue;
        // Where the line passes onto another surface (a crease, a step, a
        // silhouette) near the sheet, each surface is searched up to the
        // break: the sheet may cross a surface after its last pixel centre,
        // or cross two surfaces within one pixel, with no sign change between
        // the pixel centres. Near: a sheet crossing a's surface before the
        // break lies within the part of it that one pixel sees, as does one
        // crossing b's surface after it. A silhouette (a hit beside a miss) is
        // near by the same measure on its one surface: the sky beyond it has
        // none to cross.
        const bool near = within_a_pixel(a) || within_a_pixel(b);
        if (!near || !scanner.MayBreak(a, b)) {
          add_root(pos[i], a, pos[i + 1], b);
          continue;
        }
        double s = pos[i];
        const Sample* from = &a;
        for (const LineScanner::Break& br : breaks_at(i)) {
          add_root(s, *from, br.s_a, br.a);
          s = br.s_b, from = &br.b;
        }
        add_root(s, *from, pos[i + 1], b);
      }
    }
  });
  std::vector<StripeCenter> all;
  for (auto& v : per_line) all.insert(all.end(), v.begin(), v.end());
  return all;
}

std::string StripeCentersCsv(const std::vector<StripeCenter>& centers) {
  std::ostringstream out;
  out << "u,v,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world\n";
  char buf[512];
  for (const auto& c : centers) {
    std::snprintf(buf, sizeof buf, "%.6f,%.6f,%d,%.9g,%.9g,%.9g,%.12g,%.12g,%.12g\n", c.u, c.v, c.plane,
                  c.p_cam.x(), c.p_cam.y(), c.p_cam.z(), c.p_world.x(), c.p_world.y(), c.p_world.z());
    out << buf;
  }
  return out.str();
}

}  // namespace lt

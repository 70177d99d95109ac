#include "render/stripe_truth.h"

#include "render/stripe_truth_scanner.h"
#include "render/stripe_truth_segments.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace lt {

using stripe_truth_detail::LineScanner;
using stripe_truth_detail::Sample;
using stripe_truth_detail::WorldSheet;
using stripe_truth_detail::kMaxBreaks;
using stripe_truth_detail::kPairCasts;

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
        out.push_back(scanner.Centre(line, ws, *root));
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
  // What no pixel centre's search reaches: candidates from the triangles.
  stripe_truth_detail::AddCentresFromSegments(scene, camera, sheets, scanner, world_from_cam, axis, per_line);
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

// The laser step of a calibration session (pipeline/calib_session.h): the
// stripe of each view's dim frame on the board, its lines grouped by sheet.
#include "pipeline/calib_session.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "core/error.h"
#include "pipeline/frame_extraction.h"
#include "pipeline/frame_image_reader.h"
#include "pipeline/stripe_extractor.h"
#include "pipeline/triangulation.h"

namespace lt {

bool GroupStripesOnFlatTarget(std::vector<StripePoint>* points, const std::vector<StripeSegment>& segments, int n,
                              SearchAxis axis, double tol_px, std::string* error) {
  auto along = [&](int i) { return axis == SearchAxis::kCols ? (*points)[size_t(i)].u : (*points)[size_t(i)].v; };
  auto across = [&](int i) { return axis == SearchAxis::kCols ? (*points)[size_t(i)].v : (*points)[size_t(i)].u; };
  std::vector<const StripeSegment*> pieces;
  for (const StripeSegment& seg : segments) {
    if (!seg.ignored) pieces.push_back(&seg);
  }
  // Pooled slope: within-piece covariance over within-piece variance.
  double sxy = 0, sxx = 0;
  for (const StripeSegment* seg : pieces) {
    double mx = 0, my = 0;
    for (int i : seg->points) mx += along(i), my += across(i);
    mx /= double(seg->points.size()), my /= double(seg->points.size());
    for (int i : seg->points) sxy += (along(i) - mx) * (across(i) - my), sxx += (along(i) - mx) * (along(i) - mx);
  }
  const double slope = sxx > 0 ? sxy / sxx : 0.0;
  std::vector<std::pair<double, const StripeSegment*>> by_intercept;
  for (const StripeSegment* seg : pieces) {
    double c = 0;
    for (int i : seg->points) c += across(i) - slope * along(i);
    by_intercept.emplace_back(c / double(seg->points.size()), seg);
  }
  std::sort(by_intercept.begin(), by_intercept.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  struct Line {
    std::vector<int> points;
    double a = 0, b = 0;  // across = a + b·along
  };
  std::vector<Line> lines;
  for (size_t k = 0; k < by_intercept.size(); ++k) {
    if (k == 0 || by_intercept[k].first - by_intercept[k - 1].first > 4 * tol_px) lines.emplace_back();
    const auto& pts = by_intercept[k].second->points;
    lines.back().points.insert(lines.back().points.end(), pts.begin(), pts.end());
  }
  for (Line& l : lines) {
    double s1 = 0, sx = 0, sy = 0, sxx2 = 0, sxy2 = 0;
    for (int i : l.points) s1 += 1, sx += along(i), sy += across(i), sxx2 += along(i) * along(i), sxy2 += along(i) * across(i);
    const double det = s1 * sxx2 - sx * sx;
    l.b = det > 1e-9 * s1 * s1 ? (s1 * sxy2 - sx * sy) / det : slope;
    l.a = (sy - l.b * sx) / s1;
    l.points.clear();
  }
  for (const StripeSegment* seg : pieces) {
    int best = -1;
    double best_d = tol_px;
    for (size_t k = 0; k < lines.size(); ++k) {
      double d = 0;
      for (int i : seg->points) d += std::abs(across(i) - (lines[k].a + lines[k].b * along(i)));
      d /= double(seg->points.size());
      if (d < best_d) best_d = d, best = int(k);
    }
    if (best >= 0) lines[size_t(best)].points.insert(lines[size_t(best)].points.end(), seg->points.begin(), seg->points.end());
  }
  // Lines with less than a fifth of the longest line's points are stray light.
  size_t longest = 0;
  for (const Line& l : lines) longest = std::max(longest, l.points.size());
  lines.erase(std::remove_if(lines.begin(), lines.end(),
                             [longest](const Line& l) { return l.points.empty() || 5 * l.points.size() < longest; }),
              lines.end());
  if (int(lines.size()) != n) {
    *error = "found " + std::to_string(lines.size()) + " stripe line(s) on the board, expected " + std::to_string(n);
    return false;
  }
  double mid = 0;
  int count = 0;
  for (const Line& l : lines) {
    for (int i : l.points) mid += along(i), ++count;
  }
  mid /= std::max(1, count);
  std::sort(lines.begin(), lines.end(), [mid](const Line& x, const Line& y) { return x.a + x.b * mid < y.a + y.b * mid; });
  for (auto& p : *points) p.plane = -1;
  for (size_t k = 0; k < lines.size(); ++k) {
    for (int i : lines[k].points) (*points)[size_t(i)].plane = int(k);
  }
  return true;
}

void SessionLaserOptions::Check() const {
  ExtractionOptions e = extraction;
  if (std::isnan(e.threshold)) e.threshold = 1;
  if (std::isnan(e.background)) e.background = 0;
  e.Check();
  if (planes < 0) throw InputError("option planes", "must be >= 0");
  plane_id.Check();
  fit.Check();
  if (!(line_tolerance_px > 0) || !std::isfinite(line_tolerance_px)) {
    throw InputError("option line_tolerance_px", "must be > 0");
  }
  if (!(edge_inset_squares >= 0) || !std::isfinite(edge_inset_squares)) {
    throw InputError("option edge_inset_squares", "must be >= 0");
  }
  corners.Check();
}

SessionLaserResult CalibrateSessionLaser(const SessionRun& run, const CheckerboardSpec& board, const Camera& camera,
                                         const SessionLaserOptions& options,
                                         const std::function<void(const std::string&)>& warn) {
  options.Check();
  SessionLaserResult r;
  const RunRig& rig = run.rig;
  r.planes = options.planes > 0 ? options.planes : int(rig.planes_in_cam.size());
  if (r.planes < 1) {
    throw InputError(run.rig_in_run ? rig.source.string() : run.dir.string(),
                     run.rig_in_run ? "the rig has no laser: give the number of planes"
                                    : "no rig.json, and no laser planes in the calibration: give the number of planes");
  }
  r.axis = options.axis ? *options.axis : rig.planes_in_cam.empty() ? SearchAxis::kRows : StripeAxis(rig.planes_in_cam);
  // Without planes (a capture whose camera came alone), the first dim frame
  // read chooses the axis: the one along which it finds more stripe points (a
  // stripe across the rows, searched along the columns, gives a point per
  // column; searched along the rows, only the few rows its width covers).
  bool axis_known = options.axis || !rig.planes_in_cam.empty();
  ExtractionOptions extraction = options.extraction;
  if (options.method_from_planes && r.planes > 1 && FindsOneStripePerLine(extraction.method)) {
    extraction.method = ExtractionMethod::kMultiCom;
  }
  r.axis_from_frame = -1;
  const LaserChannelWeights matched = MatchedChannelWeights(rig);
  // Bright and dim frames: each file tag said once, counted at the end.
  ImageFileWarner warner(warn, "frame");
  const bool warn_transfer_tags = !options.transfer_given && extraction.transfer == Transfer::kLinear;
  r.views = ReadSessionViews(run, board, options.corners, &warner);
  std::map<int, const RunFrame*> frames;
  for (const RunFrame& f : run.frames) frames.emplace(f.index, &f);

  const double inset = options.edge_inset_squares * board.square_m;
  const double margin = board.margin_squares * board.square_m;
  const double x0 = -board.square_m - margin + inset, x1 = board.cols * board.square_m + margin - inset;
  const double y0 = -board.square_m - margin + inset, y1 = board.rows * board.square_m + margin - inset;
  std::vector<LaserTargetView> target_views;
  for (size_t v = 0; v < r.views.size(); ++v) {
    const SessionView& sv = r.views[v];
    SessionLaserView lv;
    lv.view = int(v);
    if (sv.dim_frame < 0) {
      lv.note = "no laser frame follows bright frame " + std::to_string(sv.bright_frame);
    } else if (!sv.detection.ok) {
      lv.note = "board not found: " + sv.detection.reason;
    } else {
      lv.pose = EstimateTargetPose(camera, ViewOfDetection(board, sv.detection));
      if (!lv.pose.ok) lv.note = "no board pose: " + lv.pose.reason;
    }
    if (!lv.note.empty()) {
      r.laser_views.push_back(lv);
      continue;
    }
    RunFrame dim = *frames.at(sv.dim_frame);  // its bit depth may come from its file, as scan's
    const AnyImage image = ReadFrameImage(&dim, rig.camera, rig.source.string(), &warner, warn_transfer_tags);
    std::unique_ptr<StripeExtractor> chosen;
    std::vector<StripePoint> points;
    FrameExtraction fx;
    for (const SearchAxis axis : {r.axis, r.axis == SearchAxis::kRows ? SearchAxis::kCols : SearchAxis::kRows}) {
      ExtractionOptions given = extraction;
      given.axis = axis;
      // As in scan: a mosaic demosaiced, a colour frame on the laser's channels.
      FrameExtraction this_fx = RunFrameExtraction(given, dim, image, rig, matched);
      auto extractor = std::make_unique<StripeExtractor>(this_fx.options);
      std::vector<StripePoint> found;
      try {
        found = extractor->Extract(image);
      } catch (const InputError& e) {
        throw InputError(dim.image.string(), e.message());
      }
      if (!chosen || found.size() > points.size()) {
        chosen = std::move(extractor), points = std::move(found), fx = std::move(this_fx);
        if (!axis_known) r.axis = axis;
      }
      if (axis_known) break;
    }
    if (!axis_known) r.axis_from_frame = dim.index;
    axis_known = true;
    const StripeExtractor& extractor = *chosen;
    const ExtractionOptions& eo = fx.options;
    if (fx.matched_weights) r.channel_weights_source = matched.Describe();
    if (fx.mosaic_mean) {
      r.channel_weights_source = matched.missing;
      r.mosaic_mean = true;
    }
    lv.stripe_points = int(points.size());
    if (r.planes == 1) {
      for (auto& p : points) p.plane = 0;
    } else {
      PlaneIdOptions id = options.plane_id;
      id.axis = r.axis;
      id.edge_margin = std::max(id.edge_margin, extractor.resolved_options().EdgeLinesWithoutPoints() + 2);
      const int w = camera.width(), h = camera.height();
      PlaneIdentification ident = IdentifyPlanes(points, eo.roi ? *eo.roi : PixelRect{0, 0, w, h}, r.planes, id);
      std::string error;
      if (!GroupStripesOnFlatTarget(&points, ident.segments, r.planes, r.axis, options.line_tolerance_px, &error)) {
        lv.note = "frame " + std::to_string(dim.index) + " (" + std::to_string(points.size()) +
                  " stripe points): " + error;
        r.laser_views.push_back(lv);
        continue;
      }
    }
    // Keep the pixels whose rays meet the board inside its area.
    LaserTargetView tv;
    tv.cam_from_target = lv.pose.cam_from_target;
    const Pose target_from_cam = tv.cam_from_target.inverse();
    const Plane board_plane = Plane{Eigen::Vector3d::UnitZ(), 0.0}.Transformed(tv.cam_from_target);
    for (const StripePoint& p : points) {
      if (p.plane < 0) continue;
      const Eigen::Vector2d px(p.u, p.v);
      const auto ray = camera.Unproject(px);
      if (!ray) continue;
      const auto t = board_plane.IntersectRay(Eigen::Vector3d::Zero(), *ray);
      if (!t) continue;
      const Eigen::Vector3d b = target_from_cam * (*t * *ray);
      if (b.x() < x0 || b.x() > x1 || b.y() < y0 || b.y() > y1) continue;
      tv.stripe_pixels.push_back(px);
      tv.plane_ids.push_back(p.plane);
    }
    lv.on_board = int(tv.stripe_pixels.size());
    if (tv.stripe_pixels.empty()) {
      lv.note = "no stripe on the board in frame " + std::to_string(dim.index);
    } else {
      lv.used = true;
      target_views.push_back(std::move(tv));
    }
    r.laser_views.push_back(lv);
  }
  warner.SayRepeats();
  r.fits = CalibrateLaserPlanes(camera, target_views, options.fit);
  return r;
}

}  // namespace lt

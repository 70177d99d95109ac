// `lasertwin coverage RUN_DIR [--distance-mm D] [--quiet]`: how well a scan of a
// print (a run rendered from a scene with "print" and a "gcode" motion, then
// scanned) covers the beads of the moves under way at the run's start or started
// during it, as printed by its end: the share of the beads' top
// surface within D of a point measured after the nozzle laid it there, the spacing of the profiles along the
// path and the scanner's largest turn rate over the run. Writes RUN_DIR/coverage.json.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "pipeline/coverage.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan_output.h"
#include "scene/bead_geometry.h"
#include "scene/scene_file.h"
#include "scene/scene_geometry.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {
namespace {

namespace fs = std::filesystem;

struct CoverageArgs {
  std::string run_dir;
  double distance_mm = 0.5;
  bool quiet = false;
};

constexpr double kTopNormalZ = 0.7;      // faces whose world normal has z above this are "top"
constexpr double kSpacingRadiusM = 3e-3;  // profiles further apart than this do not count as neighbours
constexpr double kTurnStepS = 1e-3;      // heading sampled every millisecond for the turn rate
constexpr double kNozzleStepM = 0.05e-3;  // the nozzle's positions sampled every 0.05 mm of path for the laying times
constexpr double kLaidRadiusM = 1.5e-3;   // a bead's surface lies within this of the nozzle that laid it

// The nozzle's positions (world frame) and G-code times while it laid the beads of
// segments [first, ...) up to G-code time g1.
LayingTimes NozzleLayingTimes(const GcodeMotion& motion, size_t first, double g1) {
  const Toolpath& path = motion.toolpath->path();
  std::vector<Eigen::Vector3d> nozzle;
  std::vector<double> times;
  for (size_t k = first; k < path.segments.size() && path.segments[k].t_start_s < g1; ++k) {
    const ToolpathSegment& seg = path.segments[k];
    if (!seg.LaysBead()) continue;
    const int n = std::max(1, int(std::ceil(seg.length_m / kNozzleStepM)));
    for (int j = 0; j <= n; ++j) {
      const double t = seg.t_start_s + seg.Duration() * j / n;
      if (t > g1) break;
      nozzle.push_back(motion.world_from_gcode * path.PositionAt(t));
      times.push_back(t);
    }
  }
  return LayingTimes(std::move(nozzle), std::move(times), kLaidRadiusM);
}

void Run(const CoverageArgs& a) {
  const fs::path run(a.run_dir);
  SceneFile scene = LoadSceneFile(run / "scene.json");
  if (!scene.print) throw InputError((run / "scene.json").string(), "the scene has no \"print\": nothing to cover");
  const GcodeMotion& motion = std::get<GcodeMotion>(scene.motion);
  const Toolpath& path = motion.toolpath->path();
  const std::vector<RunFrame> frames = ReadRunManifest(run);
  double t0 = INFINITY, t1 = -INFINITY;
  for (const RunFrame& f : frames) {
    t0 = std::min(t0, f.t_start_s);
    t1 = std::max(t1, f.t_end_s);
  }
  const double g0 = std::clamp(motion.start_time_s + t0, 0.0, path.Duration());
  const double g1 = std::clamp(motion.start_time_s + t1, 0.0, path.Duration());

  // The beads printed during the run, in the world frame: their top faces.
  BeadOptions bo;
  bo.layer_height_m = scene.print->layer_height_m;
  bo.filament_diameter_m = scene.print->filament_diameter_m;
  bo.points_per_half_disc = scene.print->points_per_half_disc;
  while (bo.first_segment < path.segments.size() && path.segments[bo.first_segment].t_end_s <= g0) ++bo.first_segment;
  const Mesh beads = BeadMeshUpTo(path, g1, bo);
  std::vector<Triangle3d> top;
  for (size_t t = 0; t < beads.TriangleCount(); ++t) {
    Triangle3d tri;
    for (int k = 0; k < 3; ++k) tri[size_t(k)] = motion.world_from_gcode * beads.positions[beads.indices[3 * t + size_t(k)]].cast<double>();
    const Eigen::Vector3d n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
    if (n.norm() > 0 && n.normalized().z() > kTopNormalZ) top.push_back(tri);
  }

  // The measured points on the print (by label when the cloud has labels).
  PointCloud cloud = ReadPly(run / "cloud.ply");
  if (!cloud.world_frame) throw InputError((run / "cloud.ply").string(), "is in the camera frame: coverage needs world points");
  const SceneGeometry geometry = LoadSceneGeometry(scene);
  // Each point's G-code time: its frame's mid-exposure (the pose it was placed with).
  std::map<int, double> frame_time;
  for (const RunFrame& f : frames) frame_time[f.index] = motion.start_time_s + 0.5 * (f.t_start_s + f.t_end_s);
  std::vector<Eigen::Vector3d> points, on_print;
  std::vector<double> point_times;
  std::vector<int> print_frames;
  for (const CloudPoint& c : cloud.points) {
    const auto t = frame_time.find(c.frame);
    if (t == frame_time.end()) {
      throw InputError((run / "cloud.ply").string(), "a point of frame " + std::to_string(c.frame) +
                                                         ", which " + (run / "manifest.jsonl").string() +
                                                         " does not list (scan the run again)");
    }
    points.push_back(c.p);
    point_times.push_back(t->second);
    const bool print = !cloud.has_label ||
                       (c.label >= 0 && size_t(c.label) < geometry.instances.size() &&
                        geometry.instances[size_t(c.label)].object == scene.objects.size());
    if (print) {
      on_print.push_back(c.p);
      print_frames.push_back(c.frame);
    }
  }
  CoverageOptions co;
  co.distance_m = a.distance_mm * 1e-3;
  // A bead's surface is covered only by points measured after the nozzle laid it:
  // earlier profiles there measured the bed or the layer below, a layer height under it.
  const LayingTimes laid = NozzleLayingTimes(motion, bo.first_segment, g1);
  const CoverageStats cov =
      SurfaceCoverage(top, points, co, [&](const Eigen::Vector3d& p) { return laid.At(p); }, point_times);
  const double spacing = MedianSpacingBetweenFrames(on_print, print_frames, kSpacingRadiusM);

  // The scanner's largest turn rate over the run, sampled (corners in heading
  // mode show as turns within one step).
  double max_rate = 0, max_rate_t = g0;
  for (double t = g0; t + kTurnStepS <= g1; t += kTurnStepS) {
    double d = motion.toolpath->HeadingAt(t + kTurnStepS) - motion.toolpath->HeadingAt(t);
    d = std::remainder(d, 2 * M_PI);
    if (std::abs(d) / kTurnStepS > max_rate) max_rate = std::abs(d) / kTurnStepS, max_rate_t = t;
  }
  const nlohmann::json resolved = MotionToJson(scene.motion);
  std::string rule = resolved["orientation"].get<std::string>();
  if (resolved.contains("max_turn_deg_s")) rule += ", held to " + FormatNumber(resolved["max_turn_deg_s"].get<double>()) + " deg/s";
  if (resolved.contains("max_winding_deg")) rule += ", wound at most " + FormatNumber(resolved["max_winding_deg"].get<double>()) + " deg";
  nlohmann::json j = {{"orientation", resolved["orientation"]},
                      {"gcode_time_s", {g0, g1}},
                      {"distance_mm", a.distance_mm},
                      {"top_area_mm2", cov.area_m2 * 1e6},
                      {"covered_mm2", cov.covered_m2 * 1e6},
                      {"coverage", cov.Share()},
                      {"points", points.size()},
                      {"points_on_print", on_print.size()},
                      {"median_spacing_mm", spacing * 1e3},
                      {"max_turn_rate_deg_s", max_rate * 180 / M_PI},
                      {"turn_rate_limit_deg_s", resolved.contains("max_turn_deg_s") ? resolved["max_turn_deg_s"] : nlohmann::json()},
                      {"max_turn_rate_gcode_time_s", max_rate_t}};
  WriteFileAtomically(run / "coverage.json", j.dump(2) + "\n");
  if (a.quiet) return;
  std::cout << std::fixed << std::setprecision(1) << "coverage of the beads printed in G-code time [" << g0 << ", " << g1
            << "] s (" << rule << "): "
            << 100 * cov.Share() << "% of " << cov.area_m2 * 1e6 << " mm^2 of top surface within " << FormatNumber(a.distance_mm)
            << " mm of a point\n"
            << std::setprecision(3) << "points: " << points.size() << " (" << on_print.size()
            << " on the print), median spacing between profiles " << spacing * 1e3 << " mm\n"
            << std::setprecision(0) << "largest turn rate of the scanner: " << max_rate * 180 / M_PI
            << " deg/s (sampled every 1 ms)\n"
            << "wrote " << (run / "coverage.json").string() << "\n";
}

void Add(CLI::App& app) {
  auto args = std::make_shared<CoverageArgs>();
  auto* cmd = app.add_subcommand("coverage", "Coverage of a scanned print's beads by the measured points");
  cmd->add_option("RUN_DIR", args->run_dir, "Run folder, rendered from a print scene and scanned")->required();
  cmd->add_option("--distance-mm", args->distance_mm, "Sampling distance: a surface point is covered within it")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "No summary on stdout");
  cmd->callback([args] { Run(*args); });
}

}  // namespace

LT_REGISTER_COMMAND("coverage", Add);

}  // namespace lt::cli

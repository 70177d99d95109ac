#include "scene/motion_gcode.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "scene/gcode.h"

namespace lt {

namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kMetresPerMm = 1e-3;

std::string Fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// The flange poses the robot must reach, at every move's end and every `step` of path
// length in between; heading jumps (two directions at one instant) get both.
void MakeWaypoints(const GcodeMotion& m, const GcodeRobot& robot, std::vector<RobotWaypoint>& waypoints,
                   std::vector<int>& lines) {
  const ToolpathOrientation& o = *m.toolpath;
  const Toolpath& path = o.path();
  const Pose base_from_world = robot.world_from_base.inverse();
  const Pose cam_from_flange = (robot.flange_from_tool * robot.tool_from_cam).inverse();
  auto add = [&](double t, const Eigen::Vector3d& tip, const Eigen::Vector2d& heading, int line) {
    RobotWaypoint w;
    w.t_s = t;
    w.base_from_flange =
        base_from_world * m.world_from_gcode * GcodeFromNozzleFrame(tip, heading) * m.nozzle_from_cam * cam_from_flange;
    waypoints.push_back(w);
    lines.push_back(line);
  };
  // The heading rule without a turn rate limit jumps at corners: a waypoint on each side.
  const bool jumps = o.options().mode == OrientationMode::kHeading && o.options().max_turn_rad_s == 0;
  Eigen::Vector2d last_heading(std::nan(""), std::nan(""));
  for (size_t k = 0; k < path.segments.size(); ++k) {
    const ToolpathSegment& seg = path.segments[k];
    const int n = std::max(1, int(std::ceil(seg.length_m / robot.check_step_m)));
    if (k == 0) {
      last_heading = o.DirectionAt(seg.t_start_s);
      add(seg.t_start_s, seg.start_m, last_heading, seg.line);
    } else if (jumps && seg.xy_length_m > 0) {
      Eigen::Vector2d h = seg.TangentXy(0);
      if ((h - last_heading).norm() > 1e-12) add(seg.t_start_s, seg.start_m, h, seg.line);
    }
    for (int j = 1; j <= n; ++j) {
      const double u = double(j) / n;
      const double t = seg.t_start_s + u * seg.Duration();
      last_heading = jumps && seg.xy_length_m > 0 ? seg.TangentXy(u) : o.DirectionAt(t);
      add(t, seg.PointAt(u), last_heading, seg.line);
    }
  }
}

GcodeRobot ParseRobot(const json::Object& r, const GcodeMotion& m) {
  r.Enum("type", {"ur5e"});
  GcodeRobot robot;
  if (auto v = r.Find("world_from_base")) robot.world_from_base = ReadPose(*v);
  if (auto v = r.Find("flange_from_tool")) robot.flange_from_tool = ReadPose(*v);
  if (auto v = r.Find("tool_from_cam")) robot.tool_from_cam = ReadPose(*v);
  std::vector<double> initial = {0, -90, 90, -90, -90, 0};
  if (auto v = r.Find("initial_joints_deg")) initial = v->Numbers(6, json::Range::Closed(-360, 360));
  for (int j = 0; j < 6; ++j) robot.initial_joints[j] = initial[size_t(j)] * kDegToRad;
  robot.check_step_m = r.Number("check_step_mm", 2.0, json::Range::Positive()) * kMetresPerMm;
  robot.speed_limit_is_error = r.Enum("joint_speed_limits", "warn", {"warn", "error"}) == "error";
  r.Finish();

  auto program = std::make_shared<RobotProgram>();
  std::vector<RobotWaypoint> waypoints;
  MakeWaypoints(m, robot, waypoints, program->lines);
  program->path = SolveJointPath(waypoints, robot.initial_joints, robot.limits);
  const JointPath& jp = program->path;
  auto where = [&](const JointPathProblem& p) {
    return "waypoint " + std::to_string(p.waypoint) + " (" + m.file.string() + ":" +
           std::to_string(program->lines[p.waypoint]) + ", G-code time " + Fixed(waypoints[p.waypoint].t_s, 3) +
           " s): ";
  };
  if (jp.failure) r.Fail(where(*jp.failure) + jp.failure->Describe());
  if (robot.speed_limit_is_error && jp.first_speed_violation) {
    r.Fail(where(*jp.first_speed_violation) + jp.first_speed_violation->Describe() + " (" +
           std::to_string(jp.speed_violations) + " steps exceed a joint speed limit)");
  }
  robot.program = std::move(program);
  return robot;
}

}  // namespace

Pose GcodeFromNozzleFrame(const Eigen::Vector3d& tip_m, const Eigen::Vector2d& heading) {
  Pose p = Pose::Identity();
  p.linear().col(0) = Eigen::Vector3d(heading.x(), heading.y(), 0);
  p.linear().col(1) = Eigen::Vector3d(heading.y(), -heading.x(), 0);
  p.linear().col(2) = Eigen::Vector3d(0, 0, -1);
  p.translation() = tip_m;
  return p;
}

Pose GcodeMotion::GcodeFromNozzle(double time_s) const {
  const double t = time_s + start_time_s;
  return GcodeFromNozzleFrame(toolpath->path().PositionAt(t), toolpath->DirectionAt(t));
}

Pose GcodeMotion::WorldFromCam(double time_s) const { return world_from_gcode * GcodeFromNozzle(time_s) * nozzle_from_cam; }

Pose GcodeMotion::WorldFromTool(double time_s) const {
  if (robot) return WorldFromCam(time_s) * robot->tool_from_cam.inverse();
  return world_from_gcode * GcodeFromNozzle(time_s);
}

JointVector GcodeMotion::JointsAt(double time_s) const {
  const JointPath& jp = robot->program->path;
  if (jp.q.empty()) return robot->initial_joints;
  const double t = time_s + start_time_s;
  if (!(t > jp.t_s.front())) return jp.q.front();
  if (t >= jp.t_s.back()) return jp.q.back();
  size_t i = size_t(std::upper_bound(jp.t_s.begin(), jp.t_s.end(), t) - jp.t_s.begin());
  const double t0 = jp.t_s[i - 1], t1 = jp.t_s[i];
  const double u = t1 > t0 ? (t - t0) / (t1 - t0) : 1.0;
  return jp.q[i - 1] + u * (jp.q[i] - jp.q[i - 1]);
}

GcodeMotion ParseGcodeMotion(const json::Object& o) {
  GcodeMotion m;
  m.file = o.Get("file").ExistingFile("G-code file");
  m.orientation.mode = ParseOrientationMode(o.Enum("orientation", "caster", {"fixed", "heading", "caster", "trailing"}));
  m.orientation.caster_window_m = o.Number("caster_window_mm", 10.0, json::Range::Positive()) * kMetresPerMm;
  m.orientation.trail_m = o.Number("trail_mm", 10.0, json::Range::Positive()) * kMetresPerMm;
  if (o.Find("max_turn_deg_s")) m.orientation.max_turn_rad_s = o.Number("max_turn_deg_s", json::Range::Positive()) * kDegToRad;
  if (o.Find("max_winding_deg")) {
    if (m.orientation.max_turn_rad_s == 0) o.Get("max_winding_deg").Fail("needs max_turn_deg_s, the rate to unwind at");
    m.orientation.max_winding_rad = o.Number("max_winding_deg", json::Range::Closed(180, 1e6)) * kDegToRad;
  }
  if (auto v = o.Find("world_from_gcode")) m.world_from_gcode = ReadPose(*v);
  if (auto v = o.Find("nozzle_from_cam")) m.nozzle_from_cam = ReadPose(*v);
  m.start_time_s = o.Number("start_time_s", 0.0, json::Range::NonNegative());
  auto toolpath = std::make_shared<const Toolpath>(ReadGcode(m.file, m.file.string()));
  if (toolpath->segments.empty()) o.Get("file").Fail("the G-code file has no moves");
  m.toolpath = std::make_shared<const ToolpathOrientation>(toolpath, m.orientation);
  if (auto r = o.FindObject("robot")) m.robot = ParseRobot(*r, m);
  return m;
}

nlohmann::json GcodeMotionToJson(const GcodeMotion& m) {
  nlohmann::json j{{"type", "gcode"},
                   {"file", std::filesystem::absolute(m.file).lexically_normal().string()},
                   {"orientation", OrientationModeName(m.orientation.mode)},
                   {"caster_window_mm", m.orientation.caster_window_m / kMetresPerMm},
                   {"trail_mm", m.orientation.trail_m / kMetresPerMm},
                   {"world_from_gcode", PoseToJson(m.world_from_gcode)},
                   {"nozzle_from_cam", PoseToJson(m.nozzle_from_cam)},
                   {"start_time_s", m.start_time_s}};
  if (m.orientation.max_turn_rad_s > 0) j["max_turn_deg_s"] = m.orientation.max_turn_rad_s / kDegToRad;
  if (std::isfinite(m.orientation.max_winding_rad)) j["max_winding_deg"] = m.orientation.max_winding_rad / kDegToRad;
  if (m.robot) {
    const GcodeRobot& r = *m.robot;
    std::vector<double> initial(6);
    for (int k = 0; k < 6; ++k) initial[size_t(k)] = r.initial_joints[k] / kDegToRad;
    j["robot"] = {{"type", "ur5e"},
                  {"world_from_base", PoseToJson(r.world_from_base)},
                  {"flange_from_tool", PoseToJson(r.flange_from_tool)},
                  {"tool_from_cam", PoseToJson(r.tool_from_cam)},
                  {"initial_joints_deg", initial},
                  {"check_step_mm", r.check_step_m / kMetresPerMm},
                  {"joint_speed_limits", r.speed_limit_is_error ? "error" : "warn"}};
  }
  return j;
}

namespace {

// The filament the beads take, to set beside a slicer's "filament used" (mm).
std::string FilamentNote(const Toolpath& path) {
  const double beads_mm = path.BeadFilamentLength(false) * 1e3, in_layers_mm = path.BeadFilamentLength(true) * 1e3;
  // Blobs: fed in place beyond what makes up a retraction (primes with extra length,
  // purges in place, deliberate blobs); in no bead.
  const double blobs_mm = path.BlobFilamentLength(false) * 1e3;
  return "; filament laid in beads " + Fixed(beads_mm, 3) + " mm" +
         (in_layers_mm != beads_mm ? " (" + Fixed(in_layers_mm, 3) + " mm within the layers)" : "") +
         (blobs_mm > 0 ? ", laid in place (blobs, in no bead) " + Fixed(blobs_mm, 3) + " mm" : "") + ", net fed " +
         Fixed(path.ExtrudedLength() * 1e3, 3) + " mm (retractions subtracted)";
}

}  // namespace

std::vector<std::string> GcodeMotionNotes(const GcodeMotion& m) {
  std::vector<std::string> notes;
  const Toolpath& path = m.toolpath->path();
  const int layers = path.LayerCount();
  const int sequences = path.LayerSequences();
  notes.push_back(m.file.string() + ": " + std::to_string(path.segments.size()) + " moves, " +
                  Fixed(path.Duration(), 1) + " s at constant speed, " + Fixed(path.PathLength(), 3) + " m of path, " +
                  std::to_string(layers) + " layer" + (layers == 1 ? "" : "s") +
                  (path.layers_from_z ? " (from the extrusion heights: no layer comments)" : "") +
                  (sequences > 1 ? " in " + std::to_string(sequences) +
                                       " objects printed one after another (the layer numbers start again at each)"
                                 : "") +
                  FilamentNote(path));
  if (path.program_end_line > 0 && path.lines_after_program_end > 0) {
    notes.push_back(m.file.string() + ":" + std::to_string(path.program_end_line) + ": " + path.program_end_command +
                    " ends the program; " + std::to_string(path.lines_after_program_end) + " line" +
                    (path.lines_after_program_end == 1 ? "" : "s") + " of commands or text after it not read");
  }
  if (path.firmware_retractions + path.firmware_recoveries > 0 && !path.firmware_retraction_set) {
    notes.push_back(m.file.string() + ":" + std::to_string(path.first_firmware_retraction_line) + ": " +
                    std::to_string(path.firmware_retractions) + " G10 and " + std::to_string(path.firmware_recoveries) +
                    " G11 (firmware retraction) without M207 in the file: Marlin's defaults assumed (3 mm at 45 mm/s, "
                    "recovered at 8 mm/s, no Z hop" +
                    (path.swap_retractions > 0
                         ? "; " + std::to_string(path.swap_retractions) +
                               " of the G10 are swap retractions (G10 S1): 13 mm, recovered at 8 mm/s"
                         : std::string()) +
                    ")");
  }
  for (const ToolpathWarning& w : path.warnings) {
    notes.push_back(m.file.string() + ":" + std::to_string(w.line) + ": " + w.text +
                    (w.count > 1 ? " (" + std::to_string(w.count) + " times)" : ""));
  }
  if (!path.skipped_commands.empty()) notes.push_back(m.file.string() + ": " + path.SkippedCommandsNote());
  if (path.moves_at_power_on_feed > 0) {
    notes.push_back(m.file.string() + ":" + std::to_string(path.first_power_on_feed_line) + ": " +
                    std::to_string(path.moves_at_power_on_feed) + " move" + (path.moves_at_power_on_feed == 1 ? "" : "s") +
                    " before the first feed rate (F) timed at Marlin's power-on 1500 mm/min");
  }
  TurnRates rates = m.toolpath->ComputeTurnRates();
  std::string orientation = "orientation " + OrientationModeName(m.orientation.mode) + ": largest turn rate " +
                            Fixed(rates.MaxRateDegS(), 1) + " deg/s at G-code time " + Fixed(rates.max_rate_time_s, 3) +
                            " s";
  if (rates.jumps > 0) {
    orientation += "; " + std::to_string(rates.jumps) + " instantaneous turns, the largest " +
                   Fixed(rates.MaxJumpDeg(), 1) + " deg at " + m.file.string() + ":" +
                   std::to_string(rates.max_jump_line);
  }
  if (rates.slews > 0) {
    orientation += "; held to " + Fixed(m.orientation.max_turn_rad_s / kDegToRad, 1) + " deg/s: " +
                   std::to_string(rates.slews) + " turns at that rate behind the rule's, the longest " +
                   Fixed(rates.longest_slew_s, 3) + " s from G-code time " + Fixed(rates.longest_slew_time_s, 3) + " s";
  }
  if (std::isfinite(m.orientation.max_winding_rad)) {
    orientation += "; wound at most " + Fixed(rates.max_winding_rad / kDegToRad, 1) + " deg from the start (limit " +
                   Fixed(m.orientation.max_winding_rad / kDegToRad, 1) + "), " + std::to_string(rates.unwinds) +
                   (rates.unwinds == 1 ? " unwind" : " unwinds");
  }
  notes.push_back(orientation);
  if (m.robot) {
    const RobotProgram& p = *m.robot->program;
    const JointPath& jp = p.path;
    std::string robot = "robot ur5e: " + std::to_string(jp.q.size()) + " waypoints";
    if (jp.speed_violations > 0) {
      const JointPathProblem& w = *jp.worst_speed_violation;
      robot += ", " + std::to_string(jp.speed_violations) + " steps exceed a joint speed limit; the worst at " +
               m.file.string() + ":" + std::to_string(p.lines[w.waypoint]) + ": " + w.Describe();
    } else {
      robot += ", within the joint position and speed limits";
    }
    notes.push_back(robot);
  }
  return notes;
}

}  // namespace lt

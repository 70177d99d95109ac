// The "gcode" motion: the scanner rides on a printer's nozzle (or a robot arm that
// carries the nozzle) along the toolpath of a G-code file, turned about the nozzle by
// an orientation rule (fixed, heading, virtual caster; scene/caster.h).
//
// Frames:
//   gcode   the printer's coordinates (bed origin, z up), placed in the world by
//           world_from_gcode.
//   nozzle  origin at the nozzle tip; z along the nozzle pointing down at the bed
//           (-z of gcode); x along the heading (the direction the orientation rule
//           gives in the bed plane; +x of gcode when fixed); y = z x x, to the right of
//           the heading seen from above. With nozzle_from_cam = identity the camera
//           looks straight down with its image x along the heading.
//   cam     the camera (OpenCV axes), placed on the nozzle by nozzle_from_cam.
// world_from_cam(t) = world_from_gcode * gcode_from_nozzle(t) * nozzle_from_cam.
//
// With a robot (a UR5e carrying the nozzle): the robot's tool frame is where its TCP
// is set (flange_from_tool) and tool_from_cam is the hand-eye pose, so the flange must
// be at base_from_flange(t) = base_from_world * world_from_cam(t) * cam_from_tool *
// tool_from_flange. The joint path is solved at every move's end and every
// check_step of path length in between; the camera pose stays the exact Cartesian
// one (the robot follows the toolpath; the joints are for checking and drawing).
#pragma once

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/json_reader.h"
#include "core/pose.h"
#include "scene/caster.h"
#include "scene/toolpath.h"
#include "scene/ur5e.h"

namespace lt {

// The solved joint path of the robot, with the G-code line of each waypoint.
struct RobotProgram {
  JointPath path;
  std::vector<int> lines;
};

struct GcodeRobot {
  Pose world_from_base = Pose::Identity();
  Pose flange_from_tool = Pose::Identity();
  Pose tool_from_cam = Pose::Identity();
  JointVector initial_joints = JointVector::Zero();  // the first waypoint's solution is nearest to it
  double check_step_m = 0.002;                       // waypoint spacing along the path
  bool speed_limit_is_error = false;                 // "joint_speed_limits": "error" (else "warn")
  Ur5eLimits limits;
  std::shared_ptr<const RobotProgram> program;
};

struct GcodeMotion {
  std::filesystem::path file;  // resolved against the scene file's folder
  OrientationOptions orientation;
  Pose world_from_gcode = Pose::Identity();
  Pose nozzle_from_cam = Pose::Identity();
  double start_time_s = 0;  // G-code time at sequence time 0
  std::optional<GcodeRobot> robot;
  std::shared_ptr<const ToolpathOrientation> toolpath;  // the toolpath and its orientation rule

  // Poses at sequence time t (clamped to the toolpath's start and end).
  Pose GcodeFromNozzle(double time_s) const;
  Pose WorldFromCam(double time_s) const;
  // The tool that carries the camera: the robot's tool frame (world_from_cam ·
  // tool_from_cam⁻¹) with a robot, else the nozzle frame (world_from_gcode ·
  // gcode_from_nozzle), whose hand-eye pose is nozzle_from_cam.
  Pose WorldFromTool(double time_s) const;
  // The robot's joints at sequence time t, linear between waypoints (requires a robot).
  JointVector JointsAt(double time_s) const;
};

// The nozzle frame at a tip position with a heading direction (unit, bed plane).
Pose GcodeFromNozzleFrame(const Eigen::Vector3d& tip_m, const Eigen::Vector2d& heading);

// Parses the keys of a {"type": "gcode", ...} motion object (not "type" itself, and
// without Finish()). Reads the G-code and solves the robot's joint path. Errors name
// the scene key, or the G-code file:line; an unreachable waypoint names both.
GcodeMotion ParseGcodeMotion(const json::Object& o);
nlohmann::json GcodeMotionToJson(const GcodeMotion& m);
// What a user should know about the motion: the orientation's turn rates and, with a
// robot, its joint speed limit violations.
std::vector<std::string> GcodeMotionNotes(const GcodeMotion& m);

}  // namespace lt

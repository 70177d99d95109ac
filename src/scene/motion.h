// How the scanner moves over time: the camera pose in the world as a function of
// time. A scene's "motion" section names a type; each type has its own parser and
// pose function, so new types (pose lists, robot programs, G-code paths) slot in
// as new alternatives of the variant and new entries of the parser table.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/json_reader.h"
#include "core/pose.h"
#include "scene/motion_gcode.h"
#include "scene/pose_list.h"

namespace lt {

// The scanner stands still.
struct StaticMotion {
  Pose world_from_cam = Pose::Identity();
};

// The scanner follows time-stamped poses (scene key "pose_list"; interpolation in
// scene/pose_list.h), read from a file or written inline in the scene ("poses").
// The poses are world_from_cam, or world_from_tool when tool_from_cam (the
// hand-eye pose) is given.
struct PoseListMotion {
  std::filesystem::path file;  // resolved against the scene file's folder; empty for inline poses
  PoseFileFormat format = PoseFileFormat::kCsv;
  // true ("time_origin": "first_pose"): sequence time 0 is the first pose's time
  // stamp; false ("file"): the file's times are sequence times.
  bool time_from_first_pose = true;
  std::optional<Pose> tool_from_cam;
  std::shared_ptr<const PoseTrajectory> trajectory;  // shared: motions are copied cheaply

  Pose WorldFromCam(double time_s) const;
  // The tool pose at time t when the file holds world_from_tool (tool_from_cam given).
  std::optional<Pose> WorldFromTool(double time_s) const;
};

// The scanner rides on a printer's nozzle, or on a robot arm that carries it, along
// a G-code toolpath (scene key "gcode"; frames and keys in scene/motion_gcode.h).
using Motion = std::variant<StaticMotion, PoseListMotion, GcodeMotion>;

// Parses a "motion" object ({"type": "static", ...}); unknown types and keys are errors.
Motion ParseMotion(const json::Value& value);
// The motion when the scene has no "motion" section (static, identity pose).
Motion DefaultMotion();
// The type name as written in scene files ("static", "pose_list", "gcode").
std::string MotionTypeName(const Motion& motion);
// All type names the parser knows, for messages and documentation.
std::vector<std::string> MotionTypeNames();
// The camera pose at time t (seconds from the start of the sequence).
Pose WorldFromCamAt(const Motion& motion, double time_s);
// The pose at time t of the tool that carries the camera, for motions that have
// one: a pose list of world_from_tool poses (tool_from_cam given), and G-code
// (the robot's tool frame, or the printer's nozzle). Empty for a static scanner
// and a pose list of camera poses.
std::optional<Pose> WorldFromToolAt(const Motion& motion, double time_s);
// The motion written back as scene-file JSON (for the resolved scene.json), with
// every default written out and file paths absolute.
nlohmann::json MotionToJson(const Motion& motion);
// Facts about the motion a user should see before rendering (one line each): for
// G-code, the toolpath's size and duration, the orientation's largest turn rate and
// jumps, and a robot's joint speed limit violations. Empty for static and pose lists.
std::vector<std::string> MotionNotes(const Motion& motion);

}  // namespace lt

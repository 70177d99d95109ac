// How the scanner moves over time: the camera pose in the world as a function of
// time. A scene's "motion" section names a type; each type has its own parser and
// pose function, so new types (pose lists, robot programs, G-code paths) slot in
// as new alternatives of the variant and new entries of the parser table.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "core/json_reader.h"
#include "core/pose.h"

namespace lt {

// The scanner stands still.
struct StaticMotion {
  Pose world_from_cam = Pose::Identity();
};

using Motion = std::variant<StaticMotion>;

// Parses a "motion" object ({"type": "static", ...}); unknown types and keys are errors.
Motion ParseMotion(const json::Value& value);
// The motion when the scene has no "motion" section (static, identity pose).
Motion DefaultMotion();
// The type name as written in scene files ("static").
std::string MotionTypeName(const Motion& motion);
// All type names the parser knows, for messages and documentation.
std::vector<std::string> MotionTypeNames();
// The camera pose at time t (seconds from the start of the sequence).
Pose WorldFromCamAt(const Motion& motion, double time_s);
// The motion written back as scene-file JSON (for the resolved scene.json).
nlohmann::json MotionToJson(const Motion& motion);

}  // namespace lt

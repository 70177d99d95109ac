// What a pose file's column names say (pose_file.h): a name's unit, the axis it ends
// with, times (one column, or seconds and nanoseconds in two), the words of a name and
// whether they name another quantity than the pose, robot logs' pose columns (KUKA RSI,
// Franka's O_T_EE) and exports this reader refuses. Internal to pose_file_layout.cpp.
#pragma once

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "core/text_fields.h"  // Lower

namespace lt::pose_file_detail {

// A column name without its unit ("x [mm]", "x (m)", "x_mm", "x_m"), lower case, and that unit.
std::string NameAndUnit(std::string_view field, std::string* unit);

// The axis (0, 1, 2, or 3 for w) a name ends with after one of the prefixes, or -1.
int AxisAfter(const std::string& name, std::initializer_list<const char*> prefixes, const char* axes);

// A time column's name: its unit in seconds (the name's, else `unit`'s), 0 for
// another name, -1 for an unknown unit. `known`: the name gives the unit.
double TimeColumn(const std::string& name, const std::string& unit, bool* known);

// Columns skipped by their name alone: frame, index, image, file, id, name.
bool Skipped(const std::string& name);

// The words of a name, split at '.', '_', '-', '/' and blanks ("field.pose.position.x",
// "p_RS_R_x", PlotJuggler's "/vicon/pose/position/x"); rostopic's '%' before "%time" dropped.
std::vector<std::string> Words(const std::string& name);

// ROS's child frame: a name ending in child_frame_id or child_frame ("field.child_frame_id",
// "field.transforms0.child_frame_id"), the frame a tf or Odometry message gives the pose of.
bool ChildFrame(const std::vector<std::string>& words);

// A word of the name names another quantity than the pose (velocities, biases, ...).
bool OtherQuantity(const std::vector<std::string>& words);

enum class Kind { kNone, kTranslation, kQuaternion };

// A name of several words ending in an axis, its first or second-to-last word naming a
// position or a quaternion: EuRoC's "p_RS_R_x", "q_RS_w", ROS's "field.pose.position.x",
// "field.transform.rotation.w". The axis (0..2, 3 for w) and the kind; kNone when a word
// names another quantity or the two words disagree.
Kind WordsKind(const std::vector<std::string>& words, int* axis);

// KUKA RSI's actual Cartesian pose in a column name of two words, "X_RIst" or "RIst.X":
// 0..2 for X Y Z, 3..5 for A B C, -1 otherwise.
int RsiActual(const std::vector<std::string>& words);

// One part of a time written in two columns, as ROS messages hold a stamp: "sec" and
// "nanosec" (ROS 2: header.stamp.sec, header.stamp.nanosec), "secs" and "nsecs" (ROS 1),
// "..._sec" and "..._nsec". `part` is 1 for the seconds, 1e-9 for the nanoseconds, and
// `prefix` the name before the part ("header.stamp", "" for "secs"), which pairs them.
// False for another name.
bool TimePart(const std::vector<std::string>& words, double* part, std::string* prefix);

// Element k (0..15) of a Franka robot's end effector pose O_T_EE, a 4x4 matrix written
// column-major (libfranka's RobotState, franka_msgs/FrankaState): "O_T_EE[3]",
// "field.O_T_EE3", "/franka_states/O_T_EE.3", "O_T_EE_3". `commanded` for its desired or
// commanded pose (O_T_EE_d, O_T_EE_c, libfranka's log's cmd.O_T_EE_d). -1 for another name
// (`lower_field`: the field, lower case, unit not removed).
int FrankaPoseElement(const std::string& lower_field, bool* commanded);

// Angles derived from a quaternion beside it: PlotJuggler writes a quaternion's
// ".../orientation/roll_deg", "pitch_deg", "yaw_deg" (also without the unit, or in rad).
bool QuaternionAngles(const std::vector<std::string>& words);

// Multi-row exports this reader does not take, by their first field: why, or nullptr.
const char* ExportNotRead(const std::string& first);

}  // namespace lt::pose_file_detail

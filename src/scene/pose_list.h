// Pose lists: time-stamped poses read from a file and interpolated in time.
//
// Two file formats:
//   csv  a header line `t_s,x_m,y_m,z_m,qw,qx,qy,qz`, then one pose per line
//        (time in seconds, position in metres, rotation as a unit quaternion w first).
//   tum  the TUM RGB-D benchmark trajectory format: `timestamp tx ty tz qx qy qz qw`
//        separated by blanks (quaternion w LAST), no header.
// In both, blank lines and lines starting with '#' are ignored, as is a UTF-8 byte
// order mark at the start of the file. Times must strictly
// increase; quaternions must have unit norm to 1e-3 (they are then re-normalised;
// q and -q are the same rotation). At least two poses.
//
// Interpolation: core/pose_trajectory.h (linear, slerp, clamped at the ends).
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <vector>

#include "core/pose.h"
#include "core/pose_trajectory.h"

namespace lt {

enum class PoseFileFormat { kCsv, kTum };

// Parses pose-list text. Errors are lt::InputError naming "display_name:line"
// (bad number, wrong field count, wrong header, non-increasing time, non-unit
// quaternion) or "display_name" (too few poses).
PoseTrajectory ParsePoseList(const std::string& text, PoseFileFormat format, const std::string& display_name);
// Reads a pose-list file; errors name it as `display_name` (default: the path).
PoseTrajectory ReadPoseList(const std::filesystem::path& path, PoseFileFormat format,
                            const std::string& display_name = "");

// "csv" / "tum".
std::string PoseFileFormatName(PoseFileFormat format);

}  // namespace lt

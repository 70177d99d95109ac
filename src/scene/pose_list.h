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
// Interpolation between the two poses around t: position linear in time, rotation
// by spherical linear interpolation (slerp) along the shorter arc. Before the first
// pose the first pose holds, after the last the last one holds (clamped, no
// extrapolation).
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <vector>

#include "core/pose.h"

namespace lt {

struct PoseSample {
  double t_s = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // unit
};

enum class PoseFileFormat { kCsv, kTum };

class PoseTrajectory {
 public:
  // Throws std::invalid_argument unless there are >= 2 samples with strictly
  // increasing finite times and unit quaternions (the readers check this first
  // and report file:line).
  explicit PoseTrajectory(std::vector<PoseSample> samples);

  // The interpolated pose at time t (clamped to [StartTime(), EndTime()]).
  Pose At(double t_s) const;
  double StartTime() const { return samples_.front().t_s; }
  double EndTime() const { return samples_.back().t_s; }
  const std::vector<PoseSample>& samples() const { return samples_; }

 private:
  std::vector<PoseSample> samples_;
};

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

// Time-stamped poses interpolated in time (scene pose lists, a scan's pose file
// matched to frames by time).
//
// Interpolation between the two poses around t: position linear in time, rotation
// by spherical linear interpolation (slerp) along the shorter arc. Before the first
// pose the first pose holds, after the last the last one holds (clamped, no
// extrapolation).
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "core/pose.h"

namespace lt {

struct PoseSample {
  double t_s = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // unit
};

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

}  // namespace lt

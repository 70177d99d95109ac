#include "core/pose_trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace lt {

namespace {

constexpr double kQuaternionTolerance = 1e-3;

bool UnitQuaternion(const Eigen::Quaterniond& q) { return std::abs(q.norm() - 1.0) <= kQuaternionTolerance; }

}  // namespace

PoseTrajectory::PoseTrajectory(std::vector<PoseSample> samples) : samples_(std::move(samples)) {
  if (samples_.size() < 2) throw std::invalid_argument("a pose trajectory needs at least two poses");
  for (size_t i = 0; i < samples_.size(); ++i) {
    const PoseSample& s = samples_[i];
    if (!std::isfinite(s.t_s) || !s.position.allFinite() || !s.rotation.coeffs().allFinite()) {
      throw std::invalid_argument("pose " + std::to_string(i) + " is not finite");
    }
    if (!UnitQuaternion(s.rotation)) throw std::invalid_argument("pose " + std::to_string(i) + ": quaternion not unit");
    if (i > 0 && !(s.t_s > samples_[i - 1].t_s)) {
      throw std::invalid_argument("pose " + std::to_string(i) + ": time does not increase");
    }
    samples_[i].rotation.normalize();
  }
}

Pose PoseTrajectory::At(double t_s) const {
  Pose pose = Pose::Identity();
  if (!(t_s > samples_.front().t_s)) {  // also NaN: the first pose, never garbage
    pose.linear() = samples_.front().rotation.toRotationMatrix();
    pose.translation() = samples_.front().position;
    return pose;
  }
  if (t_s >= samples_.back().t_s) {
    pose.linear() = samples_.back().rotation.toRotationMatrix();
    pose.translation() = samples_.back().position;
    return pose;
  }
  auto it = std::upper_bound(samples_.begin(), samples_.end(), t_s,
                             [](double t, const PoseSample& s) { return t < s.t_s; });
  const PoseSample& b = *it;
  const PoseSample& a = *(it - 1);
  double u = (t_s - a.t_s) / (b.t_s - a.t_s);
  pose.translation() = a.position + u * (b.position - a.position);
  pose.linear() = a.rotation.slerp(u, b.rotation).toRotationMatrix();  // Eigen takes the shorter arc
  return pose;
}

}  // namespace lt

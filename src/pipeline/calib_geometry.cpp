#include "pipeline/calib_geometry.h"

#include <algorithm>
#include <cmath>

namespace lt {

Eigen::Matrix3d RotationExp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) {
    // First order: I + [w]x (exact to 1e-24).
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    r(0, 1) = -w.z(), r(0, 2) = w.y();
    r(1, 0) = w.z(), r(1, 2) = -w.x();
    r(2, 0) = -w.y(), r(2, 1) = w.x();
    return r;
  }
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& r) {
  // Through the quaternion: stable at small angles and near π.
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d v = q.vec();
  const double s = v.norm();
  if (s < 1e-300) return Eigen::Vector3d::Zero();
  const double angle = 2.0 * std::atan2(s, q.w());
  return v * (angle / s);
}

double RotationAngle(const Eigen::Matrix3d& r) { return RotationLog(r).norm(); }

Vector6d PoseToVector(const Pose& pose) {
  Vector6d v;
  v.head<3>() = RotationLog(pose.linear());
  v.tail<3>() = pose.translation();
  return v;
}

Pose PoseFromVector(const Eigen::Ref<const Vector6d>& v) {
  Pose p = Pose::Identity();
  p.linear() = RotationExp(v.head<3>());
  p.translation() = v.tail<3>();
  return p;
}

Pose PosePlus(const Pose& pose, const Eigen::Ref<const Vector6d>& delta) {
  Pose p = Pose::Identity();
  p.linear() = RotationExp(delta.head<3>()) * pose.linear();
  p.translation() = pose.translation() + delta.tail<3>();
  return p;
}

PoseError ComparePoses(const Pose& a, const Pose& b) {
  return {RotationAngle(a.linear() * b.linear().transpose()), (a.translation() - b.translation()).norm()};
}

}  // namespace lt

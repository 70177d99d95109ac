// Rotation and pose helpers shared by the calibration estimators.
//
// A pose as six numbers is (rotation vector, translation): the rotation vector
// is axis · angle (radians, angle in [0, π]); the translation is in metres.
// Poses are perturbed on the left: p ⊞ δ = (exp(δ_r) R, t + δ_t), so δ is a
// small rotation (radians) about the axes of the frame the pose maps into and
// a shift (metres) in that frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/pose.h"

namespace lt {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// exp: rotation vector -> rotation matrix; log: rotation -> rotation vector
// (angle in [0, π]; accurate near 0 and near π).
Eigen::Matrix3d RotationExp(const Eigen::Vector3d& rotation_vector);
Eigen::Vector3d RotationLog(const Eigen::Matrix3d& rotation);
// Angle of a rotation (radians, [0, π]).
double RotationAngle(const Eigen::Matrix3d& rotation);

Vector6d PoseToVector(const Pose& pose);
Pose PoseFromVector(const Eigen::Ref<const Vector6d>& v);
// Left perturbation: (exp(δ_r) R, t + δ_t).
Pose PosePlus(const Pose& pose, const Eigen::Ref<const Vector6d>& delta);

// How far apart two poses are: the angle of R_a R_bᵀ (radians) and |t_a − t_b| (metres).
struct PoseError {
  double rotation_rad = 0;
  double translation_m = 0;
};
PoseError ComparePoses(const Pose& a, const Pose& b);

}  // namespace lt

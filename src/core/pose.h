// Rigid transforms. A pose named b_from_a maps points in frame a to frame b:
// p_in_b = b_from_a * p_in_a. Held in double.
#pragma once

#include <Eigen/Geometry>

#include "core/json_reader.h"

namespace lt {

using Pose = Eigen::Isometry3d;

// Reads a pose object. Accepted forms (exactly one rotation key, translation
// optional, default 0):
//   {"translation_m": [x, y, z], "rotation_quat_wxyz": [w, x, y, z]}
//   {"translation_m": [...], "rotation_rpy_deg": [roll, pitch, yaw]}   R = Rz(yaw) Ry(pitch) Rx(roll)
//   {"translation_m": [...], "rotation_matrix": [[r00, r01, r02], [..], [..]]}  (rows)
//   {"look_at": {"eye_m": [...], "target_m": [...], "up": [...]}}
// look_at builds a camera-to-parent pose in the OpenCV convention (z toward the
// target, y down, x right); "up" defaults to +z, or to +y when the view is along
// z (a camera straight down or up) and "up" is not given. Quaternions and matrices must be a rotation to 1e-4
// (unit norm; orthonormal with determinant +1), then they are re-normalised.
Pose ReadPose(const json::Value& v);

// Writes a pose in the first form above (quaternion), for manifests and scene.json.
nlohmann::json PoseToJson(const Pose& pose);

// The camera pose looking from eye to target (OpenCV axes). Throws
// std::invalid_argument when eye == target or up is parallel to the view direction.
Pose LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up);

}  // namespace lt

#include "core/pose.h"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/error.h"

namespace lt {

namespace {
constexpr double kRotationTolerance = 1e-4;
constexpr double kDegToRad = M_PI / 180.0;
}  // namespace

Pose LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  Eigen::Vector3d z = target - eye;
  if (z.norm() < 1e-12) throw std::invalid_argument("eye and target coincide");
  z.normalize();
  Eigen::Vector3d x = z.cross(up);  // x = y × z with image y = -up
  if (x.norm() < 1e-9 * std::max(1.0, up.norm())) {
    throw std::invalid_argument("up is parallel to the view direction");
  }
  x.normalize();
  Eigen::Vector3d y = z.cross(x);
  Pose parent_from_cam = Pose::Identity();
  parent_from_cam.linear().col(0) = x;
  parent_from_cam.linear().col(1) = y;
  parent_from_cam.linear().col(2) = z;
  parent_from_cam.translation() = eye;
  return parent_from_cam;
}

Pose ReadPose(const json::Value& v) {
  json::Object o(v);
  if (auto look = o.FindObject("look_at")) {
    Eigen::Vector3d eye = look->Vec3("eye_m");
    Eigen::Vector3d target = look->Vec3("target_m");
    const std::optional<json::Value> up_value = look->Find("up");
    Eigen::Vector3d up = up_value ? up_value->Vec3() : Eigen::Vector3d(0, 0, 1);
    if (up_value && up.squaredNorm() == 0) up_value->Fail("must not be the zero vector");
    // The default up (+z) is parallel to a view straight down or up: then image
    // top toward +y (x right along +x looking down), as a plan view shows it.
    const Eigen::Vector3d view = target - eye;
    if (!up_value && view.squaredNorm() > 0 && view.normalized().cross(up).norm() < 1e-9) up = Eigen::Vector3d(0, 1, 0);
    look->Finish();
    // look_at is a whole pose: another form's key beside it is no unknown key.
    for (const char* key : {"translation_m", "rotation_quat_wxyz", "rotation_rpy_deg", "rotation_matrix"}) {
      if (o.Has(key)) o.Get(key).Fail("look_at gives the whole pose (eye_m is the translation): give look_at or " + std::string(key) + ", not both");
    }
    o.Finish();
    try {
      return LookAt(eye, target, up);
    } catch (const std::invalid_argument& e) {
      look->Fail(e.what());
    }
  }
  Pose pose = Pose::Identity();
  pose.translation() = o.Vec3("translation_m", Eigen::Vector3d::Zero());
  int rotations = int(o.Has("rotation_quat_wxyz")) + int(o.Has("rotation_rpy_deg")) +
                  int(o.Has("rotation_matrix"));
  if (rotations > 1) {
    o.Fail("give one of rotation_quat_wxyz, rotation_rpy_deg, rotation_matrix, not several");
  }
  if (auto q = o.Find("rotation_quat_wxyz")) {
    auto c = q->Numbers(4);
    Eigen::Quaterniond quat(c[0], c[1], c[2], c[3]);
    double n = quat.norm();
    if (std::abs(n - 1.0) > kRotationTolerance) {
      q->Fail("rotation quaternion must have unit norm, got norm " + FormatNumber(n));
    }
    pose.linear() = quat.normalized().toRotationMatrix();
  } else if (auto r = o.Find("rotation_rpy_deg")) {
    auto a = r->Numbers(3);
    pose.linear() = (Eigen::AngleAxisd(a[2] * kDegToRad, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(a[1] * kDegToRad, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(a[0] * kDegToRad, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
  } else if (auto m = o.Find("rotation_matrix")) {
    auto rows = m->Array(3, 3);
    Eigen::Matrix3d R;
    for (int i = 0; i < 3; ++i) {
      auto row = rows[i].Numbers(3);
      for (int j = 0; j < 3; ++j) R(i, j) = row[j];
    }
    double ortho = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    double det = R.determinant();
    if (ortho > kRotationTolerance || std::abs(det - 1.0) > kRotationTolerance) {
      m->Fail("must be a rotation matrix (orthonormal, determinant +1); R*R^T deviates by " +
              FormatNumber(ortho) + ", determinant " + FormatNumber(det));
    }
    pose.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  }
  o.Finish();
  return pose;
}

nlohmann::json PoseToJson(const Pose& pose) {
  Eigen::Quaterniond q(pose.linear());
  const auto& t = pose.translation();
  return {{"translation_m", {t.x(), t.y(), t.z()}},
          {"rotation_quat_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
}

}  // namespace lt

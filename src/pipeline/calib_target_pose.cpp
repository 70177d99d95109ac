#include "pipeline/calib_target_pose.h"

#include <cmath>

#include "core/error.h"
#include "pipeline/calib_lm.h"

namespace lt {

TargetPoseResult EstimateTargetPose(const Camera& camera, const CalibrationView& view) {
  TargetPoseResult out;
  if (view.target_points.size() != view.pixels.size()) {
    throw InputError("target pose", "the view has " + std::to_string(view.target_points.size()) +
                                        " target points but " + std::to_string(view.pixels.size()) + " pixels");
  }
  auto refuse = [&](const std::string& reason) {
    out.ok = false;
    out.reason = reason;
    return out;
  };
  const size_t n = view.pixels.size();
  if (n < 4) return refuse("a target pose needs at least 4 points, got " + std::to_string(n));
  std::vector<Eigen::Vector2d> plane_xy, normalised;
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d& p = view.target_points[k];
    if (!p.allFinite() || !view.pixels[k].allFinite()) return refuse("non-finite point " + std::to_string(k));
    if (std::abs(p.z()) > 1e-12) return refuse("the target points are not planar (z != 0)");
    const auto ray = camera.Unproject(view.pixels[k]);
    if (!ray || !(ray->z() > 0)) return refuse("pixel " + std::to_string(k) + " has no camera ray in front");
    plane_xy.emplace_back(p.x(), p.y());
    normalised.emplace_back(ray->x() / ray->z(), ray->y() / ray->z());
  }
  Eigen::Matrix3d h;
  if (!EstimateHomography(plane_xy, normalised, &h)) return refuse("degenerate target points (collinear?)");
  const Pose start = PoseFromHomography(Eigen::Matrix3d::Identity(), h);

  const CameraParams& params = camera.params();
  LmProblem problem;
  problem.num_params = 6;
  problem.num_residuals = int(2 * n);
  problem.residuals = [&](const Eigen::VectorXd& x, Eigen::VectorXd* r) {
    const Pose pose = PoseFromVector(x);
    r->resize(long(2 * n));
    for (size_t k = 0; k < n; ++k) {
      Eigen::Vector2d px;
      if (!ProjectWithModel(params, pose * view.target_points[k], &px)) return false;
      r->segment<2>(long(2 * k)) = px - view.pixels[k];
    }
    return true;
  };
  problem.plus = [](const Eigen::VectorXd& x, const Eigen::VectorXd& d) -> Eigen::VectorXd {
    return PoseToVector(PosePlus(PoseFromVector(x), d));
  };
  problem.diff_step = Eigen::VectorXd::Constant(6, 1e-7);
  problem.names = {"rx", "ry", "rz", "tx", "ty", "tz"};
  const LmSummary s = SolveLevenbergMarquardt(problem, PoseToVector(start));
  if (!s.ok) return refuse("the target pose could not be evaluated: " + s.message);
  if (!s.converged) return refuse("the target pose did not converge: " + s.message);
  out.cam_from_target = PoseFromVector(s.x);
  out.rms_px = std::sqrt(s.cost / double(2 * n));
  if (out.cam_from_target.translation().z() <= 0) return refuse("the target lies behind the camera");
  const LmCovariance cov = EstimateCovariance(s, problem.names);
  if (!cov.ok) return refuse("the target pose is not determined: " + cov.reason);
  out.pose_std = cov.stddev;
  out.ok = true;
  return out;
}

}  // namespace lt

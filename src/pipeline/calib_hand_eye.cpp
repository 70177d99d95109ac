#include "pipeline/calib_hand_eye.h"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "pipeline/option_checks.h"
#include "pipeline/calib_lm.h"

namespace lt {

namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Matrix3d ProcrustesRotation(const Eigen::Matrix3d& m) {
  // argmax_R tr(Rᵀ M) over rotations.
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

struct Motion {
  Pose a, b;  // tool_i_from_tool_j, cam_i_from_cam_j
  Eigen::Vector3d alpha, beta;  // log maps of their rotations
};

}  // namespace

void HandEyeOptions::Check() const {
  Require(std::isfinite(min_rotation_deg) && min_rotation_deg > 0 && min_rotation_deg < 180, "min_rotation_deg",
          "must be in (0, 180), got " + FormatNumber(min_rotation_deg));
  Require(std::isfinite(min_axis_angle_deg) && min_axis_angle_deg > 0 && min_axis_angle_deg <= 90,
          "min_axis_angle_deg", "must be in (0, 90], got " + FormatNumber(min_axis_angle_deg));
  Require(std::isfinite(robot_rotation_sigma_deg) && robot_rotation_sigma_deg >= 0, "robot_rotation_sigma_deg",
          "must be >= 0, got " + FormatNumber(robot_rotation_sigma_deg));
  Require(std::isfinite(robot_translation_sigma_m) && robot_translation_sigma_m >= 0, "robot_translation_sigma_m",
          "must be >= 0, got " + FormatNumber(robot_translation_sigma_m));
  Require((robot_rotation_sigma_deg > 0) == (robot_translation_sigma_m > 0), "robot_rotation_sigma_deg",
          "and robot_translation_sigma_m must both be > 0 (robot poses refined) or both 0 (held fixed)");
  Require(std::isfinite(corner_sigma_px) && corner_sigma_px > 0, "corner_sigma_px",
          "must be > 0, got " + FormatNumber(corner_sigma_px));
  Require(std::isfinite(view_rotation_sigma_deg) && view_rotation_sigma_deg > 0, "view_rotation_sigma_deg",
          "must be > 0, got " + FormatNumber(view_rotation_sigma_deg));
  Require(std::isfinite(view_translation_sigma_m) && view_translation_sigma_m > 0, "view_translation_sigma_m",
          "must be > 0, got " + FormatNumber(view_translation_sigma_m));
  Require(max_iterations >= 1, "max_iterations", "must be >= 1, got " + std::to_string(max_iterations));
}

HandEyeResult CalibrateHandEye(const std::vector<HandEyeObservation>& obs, const HandEyeOptions& options,
                               const Camera* camera) {
  options.Check();
  const int n = int(obs.size());
  for (int i = 0; i < n; ++i) {
    const auto& o = obs[size_t(i)];
    const std::string where = "observation " + std::to_string(i);
    if (o.target_points.size() != o.pixels.size()) {
      throw InputError("", where + ": " + std::to_string(o.target_points.size()) + " target points but " +
                               std::to_string(o.pixels.size()) + " pixels");
    }
    if (camera && o.pixels.size() < 4) {
      throw InputError("", where + ": the reprojection refinement needs at least 4 corners per observation, got " +
                               std::to_string(o.pixels.size()));
    }
  }
  HandEyeResult res;
  auto refuse = [&](std::string reason) {
    res.ok = false;
    res.reason = std::move(reason);
    return res;
  };
  if (n < 3) return refuse("too few views: " + std::to_string(n) + " (at least 3 are needed)");
  for (int i = 0; i < n; ++i) {
    const auto& o = obs[size_t(i)];
    if (!o.base_from_tool.matrix().allFinite() || !o.cam_from_target.matrix().allFinite()) {
      return refuse("observation " + std::to_string(i) + " has a non-finite pose");
    }
  }

  // ---- relative motions and their diagnostics
  std::vector<Motion> motions;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      Motion m;
      m.a = obs[size_t(i)].base_from_tool.inverse() * obs[size_t(j)].base_from_tool;
      m.b = obs[size_t(i)].cam_from_target * obs[size_t(j)].cam_from_target.inverse();
      m.alpha = RotationLog(m.a.linear());
      m.beta = RotationLog(m.b.linear());
      motions.push_back(m);
    }
  }
  std::vector<Eigen::Vector3d> axes;
  for (const auto& m : motions) {
    const double angle = m.alpha.norm();
    res.largest_rotation_deg = std::max(res.largest_rotation_deg, angle / kDeg);
    if (angle >= options.min_rotation_deg * kDeg) axes.push_back(m.alpha / angle);
  }
  for (size_t i = 0; i < axes.size(); ++i) {
    for (size_t j = i + 1; j < axes.size(); ++j) {
      // Angle between the axes as lines (sign-free), in [0, 90] degrees.
      const double a = std::atan2(axes[i].cross(axes[j]).norm(), std::abs(axes[i].dot(axes[j])));
      res.largest_axis_angle_deg = std::max(res.largest_axis_angle_deg, a / kDeg);
    }
  }
  if (res.largest_rotation_deg < options.min_rotation_deg) {
    return refuse("the robot rotations are too small: the largest relative rotation is " +
                  Fmt(res.largest_rotation_deg) + " degrees (at least " + Fmt(options.min_rotation_deg) +
                  " are needed)");
  }
  if (res.largest_axis_angle_deg < options.min_axis_angle_deg) {
    return refuse("the rotation axes are nearly parallel: the largest angle between two rotation axes is " +
                  Fmt(res.largest_axis_angle_deg) + " degrees (at least " + Fmt(options.min_axis_angle_deg) +
                  " are needed; rotate the tool about two different axes)");
  }

  // ---- closed form: rotation (Procrustes on the log maps), then translation
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (const auto& mo : motions) m += mo.alpha * mo.beta.transpose();
  const Eigen::Matrix3d rx = ProcrustesRotation(m);
  Eigen::MatrixXd a(3 * motions.size(), 3);
  Eigen::VectorXd b(3 * motions.size());
  for (size_t k = 0; k < motions.size(); ++k) {
    a.block<3, 3>(3 * k, 0) = motions[k].a.linear() - Eigen::Matrix3d::Identity();
    b.segment<3>(3 * k) = rx * motions[k].b.translation() - motions[k].a.translation();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < 3) return refuse("the translation of the hand-eye transform is not determined by these motions");
  Pose x = Pose::Identity();
  x.linear() = rx;
  x.translation() = qr.solve(b);
  res.closed_form_tool_from_cam = x;
  // Y: the mean of base_from_tool_i · X · cam_from_target_i.
  Eigen::Matrix3d rsum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d tsum = Eigen::Vector3d::Zero();
  for (const auto& o : obs) {
    const Pose yi = o.base_from_tool * x * o.cam_from_target;
    rsum += yi.linear();
    tsum += yi.translation();
  }
  Pose y = Pose::Identity();
  y.linear() = ProcrustesRotation(rsum);
  y.translation() = tsum / double(n);

  // ---- refinement over X, Y and the robot pose corrections δF_i
  // State: [X (rvec, t) | Y (rvec, t) | δF_0 | ... | δF_n-1]; base_from_tool_i
  // is the measured pose ⊞ δF_i. Rows: the observations of each view, then the
  // priors δF_i / σ_robot.
  res.used_reprojection = camera != nullptr;
  const bool robot_free = options.robot_rotation_sigma_deg > 0;
  const int np = 12 + (robot_free ? 6 * n : 0);
  std::vector<int> row_offset(size_t(n) + 1, 0);
  for (int i = 0; i < n; ++i) {
    row_offset[size_t(i) + 1] = row_offset[size_t(i)] + (camera ? 2 * int(obs[size_t(i)].pixels.size()) : 6);
  }
  const int obs_rows = row_offset.back();
  Vector6d robot_sigma, view_sigma;
  robot_sigma << Eigen::Vector3d::Constant(options.robot_rotation_sigma_deg * kDeg),
      Eigen::Vector3d::Constant(options.robot_translation_sigma_m);
  view_sigma << Eigen::Vector3d::Constant(options.view_rotation_sigma_deg * kDeg),
      Eigen::Vector3d::Constant(options.view_translation_sigma_m);
  auto base_from_tool = [&](const Eigen::VectorXd& s, int i) {
    const Pose& f = obs[size_t(i)].base_from_tool;
    return robot_free ? PosePlus(f, s.segment<6>(12 + 6 * i)) : f;
  };
  auto predicted = [&](const Eigen::VectorXd& s, int i) {
    return PoseFromVector(s.head<6>()).inverse() * base_from_tool(s, i).inverse() * PoseFromVector(s.segment<6>(6));
  };
  // Observation residuals of view i (already divided by their σ).
  auto view_residuals = [&](const Eigen::VectorXd& s, int i, double* out) {
    const Pose c = predicted(s, i);
    const auto& o = obs[size_t(i)];
    if (camera) {
      for (size_t k = 0; k < o.pixels.size(); ++k) {
        const auto px = camera->Project(c * o.target_points[k]);
        if (!px) return false;
        out[2 * k] = (px->x() - o.pixels[k].x()) / options.corner_sigma_px;
        out[2 * k + 1] = (px->y() - o.pixels[k].y()) / options.corner_sigma_px;
      }
    } else {
      Vector6d d;
      d << RotationLog(c.linear() * o.cam_from_target.linear().transpose()),
          c.translation() - o.cam_from_target.translation();
      for (int k = 0; k < 6; ++k) out[k] = d[k] / view_sigma[k];
    }
    return true;
  };
  LmProblem problem;
  problem.num_params = np;
  problem.num_residuals = obs_rows + (robot_free ? 6 * n : 0);
  problem.residuals = [&](const Eigen::VectorXd& s, Eigen::VectorXd* r) {
    for (int i = 0; i < n; ++i) {
      if (!view_residuals(s, i, r->data() + row_offset[size_t(i)])) return false;
    }
    if (robot_free) {
      for (int i = 0; i < n; ++i) {
        r->segment<6>(obs_rows + 6 * i) = s.segment<6>(12 + 6 * i).cwiseQuotient(robot_sigma);
      }
    }
    return true;
  };
  problem.plus = [&](const Eigen::VectorXd& s, const Eigen::VectorXd& d) {
    Eigen::VectorXd out = s + d;
    out.head<6>() = PoseToVector(PosePlus(PoseFromVector(s.head<6>()), d.head<6>()));
    out.segment<6>(6) = PoseToVector(PosePlus(PoseFromVector(s.segment<6>(6)), d.segment<6>(6)));
    return out;
  };
  // Central differences; a robot correction moves only its own view.
  auto step = [&](int param, const Eigen::VectorXd& s) {
    if (param % 6 < 3) return 1e-7;
    const double scale = param < 6    ? s.segment<3>(3).norm()
                         : param < 12 ? s.segment<3>(9).norm()
                                      : obs[size_t((param - 12) / 6)].base_from_tool.translation().norm();
    return 1e-7 * std::max(scale, 1e-2);
  };
  problem.jacobian = [&](const Eigen::VectorXd& s, Eigen::MatrixXd* j) {
    j->setZero(problem.num_residuals, np);
    Eigen::VectorXd rp(problem.num_residuals), rm(problem.num_residuals);
    for (int c = 0; c < 12; ++c) {
      const double h = step(c, s);
      Eigen::VectorXd d = Eigen::VectorXd::Zero(np);
      d[c] = h;
      if (!problem.residuals(problem.plus(s, d), &rp)) return false;
      d[c] = -h;
      if (!problem.residuals(problem.plus(s, d), &rm)) return false;
      j->col(c).head(obs_rows) = (rp - rm).head(obs_rows) / (2 * h);
    }
    if (!robot_free) return true;
    for (int i = 0; i < n; ++i) {
      const int rows = row_offset[size_t(i) + 1] - row_offset[size_t(i)];
      Eigen::VectorXd vp(rows), vm(rows);
      for (int k = 0; k < 6; ++k) {
        const int c = 12 + 6 * i + k;
        const double h = step(c, s);
        Eigen::VectorXd t = s;
        t[c] += h;
        if (!view_residuals(t, i, vp.data())) return false;
        t[c] -= 2 * h;
        if (!view_residuals(t, i, vm.data())) return false;
        j->block(row_offset[size_t(i)], c, rows, 1) = (vp - vm) / (2 * h);
        (*j)(obs_rows + 6 * i + k, c) = 1.0 / robot_sigma[k];
      }
    }
    return true;
  };
  Eigen::VectorXd s0 = Eigen::VectorXd::Zero(np);
  s0.head<6>() = PoseToVector(x);
  s0.segment<6>(6) = PoseToVector(y);
  LmOptions lm;
  lm.max_iterations = options.max_iterations;
  const LmSummary sol = SolveLevenbergMarquardt(problem, s0, lm);
  res.iterations = sol.iterations;
  if (!sol.ok) return refuse("refinement failed: " + sol.message);
  if (!sol.converged) return refuse("refinement did not converge: " + sol.message);
  res.tool_from_cam = PoseFromVector(sol.x.head<6>());
  res.base_from_target = PoseFromVector(sol.x.segment<6>(6));
  std::vector<std::string> names = {"X rx", "X ry", "X rz", "X tx", "X ty", "X tz",
                                    "Y rx", "Y ry", "Y rz", "Y tx", "Y ty", "Y tz"};
  for (int i = 0; robot_free && i < n; ++i) {
    for (const char* c : {"rx", "ry", "rz", "tx", "ty", "tz"}) names.push_back("robot pose " + std::to_string(i) + " " + c);
  }
  const LmCovariance cov = EstimateCovariance(sol, names);
  if (!cov.ok) return refuse(cov.reason);
  res.variance_factor = cov.sigma2;
  // The tangent of X is a left perturbation, i.e. about the tool axes.
  res.tool_from_cam_std = cov.stddev.head<6>();
  res.rotation_std_rad = res.tool_from_cam_std.head<3>().norm();
  res.translation_std_m = res.tool_from_cam_std.tail<3>().norm();
  if (camera) {
    res.reprojection_rms_px = options.corner_sigma_px * std::sqrt(sol.residuals.head(obs_rows).squaredNorm() / obs_rows);
  }
  double rr = 0, tt = 0;
  for (int i = 0; i < n; ++i) {
    const PoseError e = ComparePoses(predicted(sol.x, i), obs[size_t(i)].cam_from_target);
    rr += e.rotation_rad * e.rotation_rad;
    tt += e.translation_m * e.translation_m;
  }
  res.rotation_rms_rad = std::sqrt(rr / n);
  res.translation_rms_m = std::sqrt(tt / n);
  res.ok = true;
  return res;
}

}  // namespace lt

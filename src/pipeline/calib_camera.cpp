// CalibrateCamera (calib_camera.h): checks of the views, the start, the refinement of
// intrinsics and poses, and the result's uncertainties and warnings. The model in the
// refinement's state (layout, projection, residuals) is in calib_camera_model.cpp.
#include "pipeline/calib_camera.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <limits>

#include "core/error.h"
#include "pipeline/option_checks.h"
#include "pipeline/calib_camera_model.h"
#include "pipeline/calib_camera_start.h"
#include "pipeline/calib_lm.h"
#include "sensor/param_error.h"

namespace lt {

using namespace calib_camera_detail;

namespace {

std::string ViewName(size_t v) { return "view " + std::to_string(v); }

// The angle from the axis where a Kannala–Brandt distortion folds (dθ_d/dθ
// reaches 0; π without a fold), by the sensor's analysis of the lens on a
// field too small to hold the fold. Throws ParamError when θ_d is not
// positive there.
double FisheyeFoldAngle(const KannalaBrandtCoeffs& c) {
  ImageBounds centre;
  centre.x_min = centre.y_min = -1e-9;
  centre.x_max = centre.y_max = 1e-9;
  return LensDistortion::Fisheye(c, centre).fisheye_theta_max();
}

std::string Deg(double rad) { return Fmt(rad * 180.0 / M_PI, 3); }

}  // namespace

void CameraCalibrationOptions::Check() const {
  Require(min_views >= 3, "min_views", "must be >= 3, got " + std::to_string(min_views));
  Require(min_points_per_view >= 4, "min_points_per_view", "must be >= 4, got " + std::to_string(min_points_per_view));
  Require(std::isfinite(max_relative_focal_std) && max_relative_focal_std > 0, "max_relative_focal_std",
          "must be > 0, got " + FormatNumber(max_relative_focal_std));
  Require(max_iterations >= 1, "max_iterations", "must be >= 1, got " + std::to_string(max_iterations));
  Require(model == DistortionModel::kBrownConrady || !fix_k3, "fix_k3",
          std::string("holds the Brown–Conrady model's k3; the model is ") + DistortionModelName(model));
  Require(model == DistortionModel::kBrownConrady || !fix_tangential, "fix_tangential",
          std::string("holds the Brown–Conrady model's p1, p2; the model is ") + DistortionModelName(model));
  Require(fisheye_coefficients >= 0 && fisheye_coefficients <= 4, "fisheye_coefficients",
          "must be in [0, 4], got " + std::to_string(fisheye_coefficients));
  Require(model == DistortionModel::kFisheye || fisheye_coefficients == 4, "fisheye_coefficients",
          std::string("holds the fisheye model's coefficients; the model is ") + DistortionModelName(model));
  Require(std::isfinite(fisheye_field_margin_deg) && fisheye_field_margin_deg >= 0 && fisheye_field_margin_deg <= 90,
          "fisheye_field_margin_deg", "must be in [0, 90], got " + FormatNumber(fisheye_field_margin_deg));
}

CameraCalibrationResult CalibrateCamera(const std::vector<CalibrationView>& views, int width, int height,
                                        const CameraCalibrationOptions& options) {
  options.Check();
  if (width <= 0 || height <= 0) throw InputError("", "image size must be positive");
  for (size_t v = 0; v < views.size(); ++v) {
    if (views[v].target_points.size() != views[v].pixels.size()) {
      throw InputError("", ViewName(v) + ": " + std::to_string(views[v].target_points.size()) + " target points but " +
                               std::to_string(views[v].pixels.size()) + " pixels");
    }
  }
  CameraCalibrationResult res;
  res.param_names = ParamNames(options.model);
  auto refuse = [&](std::string reason) {
    res.ok = false;
    res.reason = std::move(reason);
    return res;
  };
  if (int(views.size()) < options.min_views) {
    return refuse("too few views: " + std::to_string(views.size()) + " (at least " + std::to_string(options.min_views) +
                  " are needed)");
  }

  // ---- per view: planarity, corner count, spread, homography
  std::vector<Eigen::Matrix3d> homographies;
  size_t total_points = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    const auto& view = views[v];
    if (int(view.pixels.size()) < options.min_points_per_view) {
      return refuse(ViewName(v) + " has too few corners: " + std::to_string(view.pixels.size()) + " (at least " +
                    std::to_string(options.min_points_per_view) + ")");
    }
    std::vector<Eigen::Vector2d> xy;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    double extent = 0;
    for (size_t k = 0; k < view.pixels.size(); ++k) {
      const Eigen::Vector3d& p = view.target_points[k];
      if (!p.allFinite() || !view.pixels[k].allFinite()) return refuse(ViewName(v) + " has a non-finite coordinate");
      xy.push_back(p.head<2>());
      mean += p.head<2>();
      extent = std::max(extent, p.head<2>().cwiseAbs().maxCoeff());
    }
    for (const auto& p : view.target_points) {
      if (std::abs(p.z()) > 1e-9 * std::max(extent, 1e-3)) {
        return refuse(ViewName(v) + ": the target points are not planar (z must be 0 in the target frame)");
      }
    }
    mean /= double(xy.size());
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& p : xy) scatter += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> se(scatter);
    if (!(se.eigenvalues()[0] > 1e-6 * se.eigenvalues()[1])) {
      return refuse(ViewName(v) + ": the corners are collinear");
    }
    Eigen::Matrix3d h;
    if (!EstimateHomography(xy, view.pixels, &h)) return refuse(ViewName(v) + ": no homography fits the corners");
    homographies.push_back(h);
    total_points += view.pixels.size();
  }

  // ---- closed form
  Eigen::Matrix3d k;
  std::vector<Eigen::Matrix3d> start_homographies = homographies;
  bool closed_form = false;
  if (options.model == DistortionModel::kFisheye) {
    // A wide lens's board is far from a projective image of a plane: the
    // start is that of an equidistant lens (FisheyeStart), whose pixels lifted
    // to a pinhole's give the homographies.
    closed_form = FisheyeStart(views, width, height, &k, &start_homographies);
  }
  if (!closed_form) {
    start_homographies = homographies;
    closed_form = ClosedFormIntrinsics(homographies, width, height, &k);
  }
  if (!closed_form) {
    return refuse(
        "closed-form intrinsics do not exist for these views (the image of the absolute conic is not positive "
        "definite): the views are too close to parallel to the image plane, or too few");
  }
  res.closed_form_fx = k(0, 0), res.closed_form_fy = k(1, 1), res.closed_form_cx = k(0, 2), res.closed_form_cy = k(1, 2);
  for (const auto& h : start_homographies) res.closed_form_cam_from_target.push_back(PoseFromHomography(k, h));

  // ---- refinement
  Layout layout;
  layout.model = options.model;
  layout.intrinsic_count = 4 + DistortionCount(options.model);
  layout.views = int(views.size());
  for (int i = 0; i < layout.intrinsic_count; ++i) {
    const bool tangential = options.model == DistortionModel::kBrownConrady && (i == 6 || i == 7);
    const bool k3 = options.model == DistortionModel::kBrownConrady && i == 8;
    const bool fisheye_held = options.model == DistortionModel::kFisheye && i >= 4 + options.fisheye_coefficients;
    if ((tangential && options.fix_tangential) || (k3 && options.fix_k3) || fisheye_held) continue;
    layout.free_intrinsics.push_back(i);
  }
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(layout.StateSize());
  x0[0] = k(0, 0), x0[1] = k(1, 1), x0[2] = k(0, 2), x0[3] = k(1, 2);
  for (int v = 0; v < layout.views; ++v) {
    x0.segment<6>(layout.PoseOffset(v)) = PoseToVector(res.closed_form_cam_from_target[size_t(v)]);
  }
  std::vector<int> row_offset(views.size() + 1, 0);
  for (size_t v = 0; v < views.size(); ++v) row_offset[v + 1] = row_offset[v] + 2 * int(views[v].pixels.size());

  LmProblem problem;
  problem.num_params = layout.TangentSize();
  problem.num_residuals = row_offset.back();
  problem.residuals = [&](const Eigen::VectorXd& x, Eigen::VectorXd* r) {
    const CameraParams p = ParamsFromState(layout, x, width, height);
    for (int v = 0; v < layout.views; ++v) {
      const Pose pose = PoseFromVector(x.segment<6>(layout.PoseOffset(v)));
      if (!ViewResiduals(p, pose, views[size_t(v)], r->data() + row_offset[size_t(v)])) return false;
    }
    return true;
  };
  problem.plus = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& d) {
    Eigen::VectorXd y = x;
    for (size_t i = 0; i < layout.free_intrinsics.size(); ++i) y[layout.free_intrinsics[i]] += d[int(i)];
    for (int v = 0; v < layout.views; ++v) {
      const Pose pose = PoseFromVector(x.segment<6>(layout.PoseOffset(v)));
      y.segment<6>(layout.PoseOffset(v)) = PoseToVector(PosePlus(pose, d.segment<6>(layout.TangentPose(v))));
    }
    return y;
  };
  // Central differences, view by view: a pose moves only its own view's residuals.
  problem.jacobian = [&](const Eigen::VectorXd& x, Eigen::MatrixXd* j) {
    j->setZero(problem.num_residuals, problem.num_params);
    Eigen::VectorXd rp(problem.num_residuals), rm(problem.num_residuals);
    for (size_t i = 0; i < layout.free_intrinsics.size(); ++i) {
      const int si = layout.free_intrinsics[i];
      const double h = si < 4 ? 1e-6 * x[0] : 1e-7;
      Eigen::VectorXd xp = x, xm = x;
      xp[si] += h;
      xm[si] -= h;
      if (!problem.residuals(xp, &rp) || !problem.residuals(xm, &rm)) return false;
      j->col(int(i)) = (rp - rm) / (2 * h);
    }
    const CameraParams p = ParamsFromState(layout, x, width, height);
    for (int v = 0; v < layout.views; ++v) {
      const Pose pose = PoseFromVector(x.segment<6>(layout.PoseOffset(v)));
      const int rows = row_offset[size_t(v) + 1] - row_offset[size_t(v)];
      Eigen::VectorXd vp(rows), vm(rows);
      for (int d = 0; d < 6; ++d) {
        const double h = d < 3 ? 1e-6 : 1e-6 * std::max(pose.translation().norm(), 1e-3);
        Vector6d delta = Vector6d::Zero();
        delta[d] = h;
        if (!ViewResiduals(p, PosePlus(pose, delta), views[size_t(v)], vp.data())) return false;
        delta[d] = -h;
        if (!ViewResiduals(p, PosePlus(pose, delta), views[size_t(v)], vm.data())) return false;
        j->block(row_offset[size_t(v)], layout.TangentPose(v) + d, rows, 1) = (vp - vm) / (2 * h);
      }
    }
    return true;
  };
  LmOptions lm;
  lm.max_iterations = options.max_iterations;
  const LmSummary sol = SolveLevenbergMarquardt(problem, x0, lm);
  res.iterations = sol.iterations;
  res.solver_message = sol.message;
  if (!sol.ok) return refuse("refinement failed: " + sol.message);
  if (!sol.converged) return refuse("refinement did not converge: " + sol.message);

  // ---- results and uncertainty
  const Eigen::VectorXd& x = sol.x;
  res.camera = ParamsFromState(layout, x, width, height);
  res.params = x.head(layout.intrinsic_count);
  res.rms_px = std::sqrt(sol.cost / double(problem.num_residuals));
  for (size_t v = 0; v < views.size(); ++v) {
    const int rows = row_offset[v + 1] - row_offset[v];
    res.view_rms_px.push_back(std::sqrt(sol.residuals.segment(row_offset[v], rows).squaredNorm() / rows));
    res.cam_from_target.push_back(PoseFromVector(x.segment<6>(layout.PoseOffset(int(v)))));
  }
  std::vector<std::string> tangent_names;
  for (int i : layout.free_intrinsics) tangent_names.push_back(res.param_names[size_t(i)]);
  for (size_t v = 0; v < views.size(); ++v) {
    for (const char* n : {"rx", "ry", "rz", "tx", "ty", "tz"}) tangent_names.push_back(ViewName(v) + " " + n);
  }
  const LmCovariance cov = EstimateCovariance(sol, tangent_names);
  if (!cov.ok) return refuse(cov.reason);
  res.sigma_px = std::sqrt(cov.sigma2);
  const int nf = int(layout.free_intrinsics.size());
  res.param_std = Eigen::VectorXd::Zero(layout.intrinsic_count);
  res.param_covariance = Eigen::MatrixXd::Zero(layout.intrinsic_count, layout.intrinsic_count);
  for (int a = 0; a < nf; ++a) {
    res.param_std[layout.free_intrinsics[size_t(a)]] = cov.stddev[a];
    for (int b = 0; b < nf; ++b) {
      res.param_covariance(layout.free_intrinsics[size_t(a)], layout.free_intrinsics[size_t(b)]) = cov.covariance(a, b);
    }
  }
  for (int v = 0; v < layout.views; ++v) res.pose_std.push_back(cov.stddev.segment<6>(layout.TangentPose(v)));
  for (int i : {0, 1}) {
    const double rel = res.param_std[i] / res.params[i];
    if (!(res.params[i] > 0) || !(rel <= options.max_relative_focal_std)) {
      return refuse("the focal length is poorly determined (" + res.param_names[size_t(i)] + " = " +
                    Fmt(res.params[i], 6) + " ± " + Fmt(res.param_std[i], 2) +
                    " px): the views are too close to parallel to the image plane or too few");
    }
  }
  // ---- the field the views observed
  for (size_t v = 0; v < views.size(); ++v) {
    for (size_t i = 0; i < views[v].pixels.size(); ++i) {
      const Eigen::Vector3d q = res.cam_from_target[v] * views[v].target_points[i];
      res.observed_field_rad = std::max(res.observed_field_rad, std::atan2(q.head<2>().norm(), q.z()));
      const Eigen::Vector2d t((views[v].pixels[i].x() - res.camera.cx) / res.camera.fx,
                              (views[v].pixels[i].y() - res.camera.cy) / res.camera.fy);
      res.observed_radius = std::max(res.observed_radius, t.norm());
    }
  }
  std::optional<double> fisheye_fold;  // a fold beyond the observed field: its angle
  if (options.model == DistortionModel::kFisheye) {
    // Only the field the boards observed (plus the margin) has to be free of
    // a fold: a fit that folds there does not describe the views.
    const double field = std::min(M_PI, res.observed_field_rad + options.fisheye_field_margin_deg * M_PI / 180.0);
    double fold = M_PI;
    try {
      fold = FisheyeFoldAngle(res.camera.fisheye);
    } catch (const ParamError& e) {
      return refuse(std::string("the estimated camera is not valid: ") + e.what());
    }
    if (fold <= field) {
      return refuse("the fisheye distortion folds at " + Deg(fold) + " deg from the axis, within the field the boards "
                    "observed (corners up to " + Deg(res.observed_field_rad) + " deg from the axis, checked to " +
                    Deg(field) + " deg): the model does not describe the views");
    }
    if (fold < M_PI) fisheye_fold = fold;
  }
  try {
    Camera check(res.camera);
  } catch (const ParamError& e) {
    // A distortion that folds inside the image: the views do not reach far
    // enough toward the image's corners to hold the model's highest term.
    // Brown–Conrady's k3 (r^6) is the usual one: the fit again without it.
    const bool k3_free = options.model == DistortionModel::kBrownConrady && !options.fix_k3;
    if (k3_free) {
      CameraCalibrationOptions without_k3 = options;
      without_k3.fix_k3 = true;
      CameraCalibrationResult again = CalibrateCamera(views, width, height, without_k3);
      if (again.ok) {
        again.note = "k3 held at 0: with k3 free (" + Fmt(res.params[8], 4) + ") the estimated camera is not valid (" +
                     e.what() + "); views with the board nearer the image's corners would determine it";
        return again;
      }
    }
    // A fisheye that folds beyond the observed field, inside the image: its
    // highest free coefficient extrapolates wildly there. The fit again with
    // it held at 0 (k1 and k2 stay free).
    if (fisheye_fold) {
      const int n = options.fisheye_coefficients;
      std::string why = "the fisheye distortion folds at " + Deg(*fisheye_fold) + " deg from the axis, beyond the "
                        "field the boards observed (corners up to " + Deg(res.observed_field_rad) + " deg) but inside "
                        "the image";
      if (n <= 2) return refuse(why + ": add views with the board nearer the image's corners");
      CameraCalibrationOptions fewer = options;
      fewer.fisheye_coefficients = n - 1;
      CameraCalibrationResult again = CalibrateCamera(views, width, height, fewer);
      if (!again.ok) return refuse(why + "; with k" + std::to_string(n) + " held at 0: " + again.reason);
      if (again.note.empty()) {
        again.note = "k" + std::to_string(n) + (n < 4 ? "..k4" : "") + " held at 0: with k" + std::to_string(n) +
                     " free (" + Fmt(res.params[3 + n], 4) + ") " + why;
      }
      return again;
    }
    return refuse(std::string("the estimated camera is not valid: ") + e.what() +
                  ": the views do not reach far enough toward the image's corners to determine the distortion "
                  "there; add views with the board nearer the corners");
  }
  res.ok = true;
  return res;
}

}  // namespace lt

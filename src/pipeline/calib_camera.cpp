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
#include "pipeline/calib_lm.h"
#include "sensor/param_error.h"

namespace lt {

namespace {

// The pixel of camera-frame point (X, Y, Z) under the model (formulas of
// sensor/distortion.h).
bool ProjectScalar(const CameraParams& p, double X, double Y, double Z, double* u, double* v) {
  double tx, ty;
  if (p.distortion == DistortionModel::kFisheye) {
    const double r = std::sqrt(X * X + Y * Y);
    if (r == 0 && !(Z > 0)) return false;
    if (r < 1e-12 * std::abs(Z)) {
      tx = X / Z, ty = Y / Z;  // θ_d/θ → 1 on the axis
    } else {
      const double s = p.fisheye.ThetaD(std::atan2(r, Z)) / r;
      tx = s * X, ty = s * Y;
    }
  } else {
    if (!(Z > 0)) return false;
    const double x = X / Z, y = Y / Z;
    if (p.distortion == DistortionModel::kBrownConrady) {
      const BrownConradyCoeffs& c = p.brown_conrady;
      const double r2 = x * x + y * y;
      const double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
      tx = x * radial + 2.0 * c.p1 * x * y + c.p2 * (r2 + 2.0 * x * x);
      ty = y * radial + c.p1 * (r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y;
    } else {
      tx = x, ty = y;
    }
  }
  *u = p.fx * tx + p.cx;
  *v = p.fy * ty + p.cy;
  return std::isfinite(*u) && std::isfinite(*v);
}

int DistortionCount(DistortionModel m) {
  switch (m) {
    case DistortionModel::kNone: return 0;
    case DistortionModel::kBrownConrady: return 5;
    case DistortionModel::kFisheye: return 4;
  }
  return 0;
}

std::vector<std::string> ParamNames(DistortionModel m) {
  std::vector<std::string> n = {"fx", "fy", "cx", "cy"};
  if (m == DistortionModel::kBrownConrady) n.insert(n.end(), {"k1", "k2", "p1", "p2", "k3"});
  if (m == DistortionModel::kFisheye) n.insert(n.end(), {"k1", "k2", "k3", "k4"});
  return n;
}

// State layout: [fx fy cx cy | distortion | pose_0 (rvec, t) | pose_1 | ...].
struct Layout {
  DistortionModel model;
  int intrinsic_count;            // 4 + distortion count
  std::vector<int> free_intrinsics;  // state indices of the free intrinsics
  int views;
  int PoseOffset(int v) const { return intrinsic_count + 6 * v; }
  int StateSize() const { return intrinsic_count + 6 * views; }
  int TangentSize() const { return int(free_intrinsics.size()) + 6 * views; }
  int TangentPose(int v) const { return int(free_intrinsics.size()) + 6 * v; }
};

CameraParams ParamsFromState(const Layout& l, const Eigen::VectorXd& x, int width, int height) {
  CameraParams p;
  p.width = width;
  p.height = height;
  p.fx = x[0], p.fy = x[1], p.cx = x[2], p.cy = x[3];
  p.distortion = l.model;
  if (l.model == DistortionModel::kBrownConrady) {
    p.brown_conrady = {x[4], x[5], x[6], x[7], x[8]};
  } else if (l.model == DistortionModel::kFisheye) {
    p.fisheye = {x[4], x[5], x[6], x[7]};
  }
  return p;
}

// Residuals (projection − detection, pixels) of one view into out[0 .. 2n).
// Scalar arithmetic: this is the inner loop of the refinement.
bool ViewResiduals(const CameraParams& p, const Pose& cam_from_target, const CalibrationView& view, double* out) {
  const Eigen::Matrix3d r = cam_from_target.linear();
  const Eigen::Vector3d t = cam_from_target.translation();
  const double r00 = r(0, 0), r01 = r(0, 1), r02 = r(0, 2), r10 = r(1, 0), r11 = r(1, 1), r12 = r(1, 2), r20 = r(2, 0),
               r21 = r(2, 1), r22 = r(2, 2), t0 = t.x(), t1 = t.y(), t2 = t.z();
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double) && sizeof(Eigen::Vector2d) == 2 * sizeof(double));
  const size_t n = view.pixels.size();
  if (n == 0) return true;
  const double* pts = view.target_points.data()->data();
  const double* obs = view.pixels.data()->data();
  for (size_t k = 0; k < n; ++k) {
    const double x = pts[3 * k], y = pts[3 * k + 1], z = pts[3 * k + 2];
    double u, v;
    if (!ProjectScalar(p, r00 * x + r01 * y + r02 * z + t0, r10 * x + r11 * y + r12 * z + t1,
                       r20 * x + r21 * y + r22 * z + t2, &u, &v)) {
      return false;
    }
    out[2 * k] = u - obs[2 * k];
    out[2 * k + 1] = v - obs[2 * k + 1];
  }
  return true;
}

// Nearest rotation matrix (SVD, determinant +1).
Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

Eigen::Matrix<double, 1, 6> ZhangRow(const Eigen::Matrix3d& h, int i, int j) {
  Eigen::Matrix<double, 1, 6> v;
  v << h(0, i) * h(0, j), h(0, i) * h(1, j) + h(1, i) * h(0, j), h(1, i) * h(1, j),
      h(2, i) * h(0, j) + h(0, i) * h(2, j), h(2, i) * h(1, j) + h(1, i) * h(2, j), h(2, i) * h(2, j);
  return v;
}

// Zhang's closed form with zero skew. Homographies are first expressed in
// normalised pixels (centre of the image at 0, half-size 1) for conditioning.
bool ClosedFormIntrinsics(const std::vector<Eigen::Matrix3d>& homographies, int width, int height,
                          Eigen::Matrix3d* k) {
  const double s = 0.5 * (width + height) * 0.5;
  Eigen::Matrix3d t;
  t << 1 / s, 0, -0.5 * (width - 1) / s, 0, 1 / s, -0.5 * (height - 1) / s, 0, 0, 1;
  Eigen::MatrixXd v(2 * homographies.size() + 1, 6);
  for (size_t i = 0; i < homographies.size(); ++i) {
    Eigen::Matrix3d h = t * homographies[i];
    h /= h.norm();
    v.row(2 * i) = ZhangRow(h, 0, 1);
    v.row(2 * i + 1) = ZhangRow(h, 0, 0) - ZhangRow(h, 1, 1);
  }
  v.row(v.rows() - 1) << 0, 1, 0, 0, 0, 0;  // zero skew: B12 = 0
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(v, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  if (!(sv[4] > 1e-12 * sv[0])) return false;  // the null space is not one-dimensional
  const Eigen::VectorXd b = svd.matrixV().col(5);
  const double b11 = b[0], b12 = b[1], b22 = b[2], b13 = b[3], b23 = b[4], b33 = b[5];
  const double den = b11 * b22 - b12 * b12;
  if (!(den > 0)) return false;
  const double v0 = (b12 * b13 - b11 * b23) / den;
  const double lambda = b33 - (b13 * b13 + v0 * (b12 * b13 - b11 * b23)) / b11;
  const double a2 = lambda / b11, b2 = lambda * b11 / den;
  if (!(a2 > 0 && b2 > 0)) return false;
  const double alpha = std::sqrt(a2), beta = std::sqrt(b2);
  const double gamma = -b12 * alpha * alpha * beta / lambda;
  const double u0 = gamma * v0 / beta - b13 * alpha * alpha / lambda;
  Eigen::Matrix3d kn;
  kn << alpha, 0, u0, 0, beta, v0, 0, 0, 1;
  *k = t.inverse() * kn;
  return k->allFinite();
}

Pose ClosedFormExtrinsics(const Eigen::Matrix3d& k, const Eigen::Matrix3d& h) {
  Eigen::Matrix3d a = k.inverse() * h;
  double scale = 1.0 / a.col(0).norm();
  if (a(2, 2) * scale < 0) scale = -scale;  // the target lies in front of the camera
  Eigen::Matrix3d r;
  r.col(0) = scale * a.col(0);
  r.col(1) = scale * a.col(1);
  r.col(2) = r.col(0).cross(r.col(1));
  Pose pose = Pose::Identity();
  pose.linear() = NearestRotation(r);
  pose.translation() = scale * a.col(2);
  return pose;
}

std::string ViewName(size_t v) { return "view " + std::to_string(v); }

}  // namespace

Pose PoseFromHomography(const Eigen::Matrix3d& camera_matrix, const Eigen::Matrix3d& homography) {
  return ClosedFormExtrinsics(camera_matrix, homography);
}

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
}

bool ProjectWithModel(const CameraParams& p, const Eigen::Vector3d& q, Eigen::Vector2d* pixel) {
  double u, v;
  if (!ProjectScalar(p, q.x(), q.y(), q.z(), &u, &v)) return false;
  *pixel = {u, v};
  return true;
}

bool EstimateHomography(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& to,
                        Eigen::Matrix3d* homography) {
  const size_t n = from.size();
  if (n < 4 || to.size() != n) return false;
  auto normaliser = [](const std::vector<Eigen::Vector2d>& pts) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const auto& p : pts) c += p;
    c /= double(pts.size());
    double d = 0;
    for (const auto& p : pts) d += (p - c).norm();
    d /= double(pts.size());
    const double s = d > 0 ? std::sqrt(2.0) / d : 1.0;
    Eigen::Matrix3d t;
    t << s, 0, -s * c.x(), 0, s, -s * c.y(), 0, 0, 1;
    return t;
  };
  const Eigen::Matrix3d tf = normaliser(from), tt = normaliser(to);
  Eigen::MatrixXd a(2 * n, 9);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = tf * from[i].homogeneous();
    const Eigen::Vector3d q = tt * to[i].homogeneous();
    const double x = p.x(), y = p.y(), u = q.x(), v = q.y();
    a.row(2 * i) << -x, -y, -1, 0, 0, 0, u * x, u * y, u;
    a.row(2 * i + 1) << 0, 0, 0, -x, -y, -1, v * x, v * y, v;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  if (!(sv[7] > 1e-10 * sv[0])) return false;
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d hn;
  hn << h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7], h[8];
  Eigen::Matrix3d out = tt.inverse() * hn * tf;
  if (!(std::abs(out(2, 2)) > 1e-300)) return false;
  *homography = out / out(2, 2);
  return homography->allFinite();
}

namespace {

// An equidistant lens (r = f θ about the image centre) seen as a pinhole: the
// pixel's ray, on the plane z = 1. Rays beyond 80° from the axis are left out
// (their tangent runs away).
std::optional<Eigen::Vector2d> LiftEquidistant(const Eigen::Vector2d& px, const Eigen::Vector2d& centre, double f) {
  const Eigen::Vector2d d = (px - centre) / f;
  const double theta = d.norm();
  if (theta >= 80.0 * M_PI / 180.0) return std::nullopt;
  return theta > 0 ? Eigen::Vector2d(d * (std::tan(theta) / theta)) : Eigen::Vector2d(d);
}

// The start of a fisheye calibration: Zhang's closed form on distorted pixels
// fails for a wide lens (a board spanning 90° of the field is no homography
// of the plane), so the lens is first taken as equidistant about the image
// centre, the Kannala–Brandt model with k1..k4 = 0. Its focal length is the
// one, on a geometric ladder from a 10° to a 200° diagonal field, whose lifted
// corners fit a homography per view best (RMS in pixels, through the same
// lens); the ladder's step (3%) is refined by a parabola through the best
// rung and its neighbours. Returns K = [f 0 cx; 0 f cy] and the homographies
// of the lifted corners (pinhole coordinates, K = identity); false when no
// focal length fits every view.
bool FisheyeStart(const std::vector<CalibrationView>& views, int width, int height, Eigen::Matrix3d* k,
                  std::vector<Eigen::Matrix3d>* lifted_homographies) {
  const Eigen::Vector2d centre(0.5 * (width - 1), 0.5 * (height - 1));
  const double half_diagonal = centre.norm();
  auto fit = [&](double f, std::vector<Eigen::Matrix3d>* hs) {
    double sum2 = 0;
    size_t n = 0;
    if (hs) hs->clear();
    for (const CalibrationView& view : views) {
      std::vector<Eigen::Vector2d> from, to, seen;
      for (size_t i = 0; i < view.pixels.size(); ++i) {
        const auto q = LiftEquidistant(view.pixels[i], centre, f);
        if (!q) continue;
        from.push_back(view.target_points[i].head<2>());
        to.push_back(*q);
        seen.push_back(view.pixels[i]);
      }
      Eigen::Matrix3d h;
      if (from.size() < 4 || !EstimateHomography(from, to, &h)) return std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < from.size(); ++i) {
        const Eigen::Vector3d q = h * from[i].homogeneous();
        if (!(q.z() > 0)) return std::numeric_limits<double>::infinity();
        const Eigen::Vector2d m = q.head<2>() / q.z();
        const double r = m.norm();
        const Eigen::Vector2d px = centre + (r > 0 ? Eigen::Vector2d(m * (f * std::atan(r) / r)) : Eigen::Vector2d(f * m));
        sum2 += (px - seen[i]).squaredNorm();
        ++n;
      }
      if (hs) hs->push_back(h);
    }
    return n > 0 ? std::sqrt(sum2 / double(n)) : std::numeric_limits<double>::infinity();
  };
  // f = half diagonal / half field angle: 100° (wide) to 5° (narrow) half fields.
  const double f_min = half_diagonal / (100.0 * M_PI / 180.0), f_max = half_diagonal / (5.0 * M_PI / 180.0);
  const double step = std::log(1.03);
  std::vector<double> fs, rms;
  for (double lf = std::log(f_min); lf <= std::log(f_max); lf += step) {
    fs.push_back(std::exp(lf));
    rms.push_back(fit(fs.back(), nullptr));
  }
  const size_t best = size_t(std::min_element(rms.begin(), rms.end()) - rms.begin());
  if (!std::isfinite(rms[best])) return false;
  double lf = std::log(fs[best]);
  if (best > 0 && best + 1 < fs.size() && std::isfinite(rms[best - 1]) && std::isfinite(rms[best + 1])) {
    const double a = rms[best - 1], b = rms[best], c = rms[best + 1];
    const double den = a - 2 * b + c;
    if (den > 0) lf += 0.5 * step * (a - c) / den;
  }
  const double f = std::exp(lf);
  if (!std::isfinite(fit(f, lifted_homographies))) return false;
  *k << f, 0, centre.x(), 0, f, centre.y(), 0, 0, 1;
  // Pinhole coordinates of the lifted corners: K = identity for the extrinsics.
  for (auto& h : *lifted_homographies) h = *k * h;
  return true;
}

}  // namespace

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
  for (const auto& h : start_homographies) res.closed_form_cam_from_target.push_back(ClosedFormExtrinsics(k, h));

  // ---- refinement
  Layout layout;
  layout.model = options.model;
  layout.intrinsic_count = 4 + DistortionCount(options.model);
  layout.views = int(views.size());
  for (int i = 0; i < layout.intrinsic_count; ++i) {
    const bool tangential = options.model == DistortionModel::kBrownConrady && (i == 6 || i == 7);
    const bool k3 = options.model == DistortionModel::kBrownConrady && i == 8;
    if ((tangential && options.fix_tangential) || (k3 && options.fix_k3)) continue;
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
    return refuse(std::string("the estimated camera is not valid: ") + e.what() +
                  ": the views do not reach far enough toward the image's corners to determine the distortion "
                  "there; add views with the board nearer the corners");
  }
  res.ok = true;
  return res;
}

}  // namespace lt

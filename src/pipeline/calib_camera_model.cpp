// The camera model in CalibrateCamera's state (calib_camera_model.h), and
// ProjectWithModel (calib_camera.h): scalar projection under each distortion model, the
// parameters of a state, and one view's residuals, the inner loop of the refinement.
#include "pipeline/calib_camera_model.h"

#include <cmath>

namespace lt {

namespace calib_camera_detail {

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

}  // namespace

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

}  // namespace calib_camera_detail

using namespace calib_camera_detail;

bool ProjectWithModel(const CameraParams& p, const Eigen::Vector3d& q, Eigen::Vector2d* pixel) {
  double u, v;
  if (!ProjectScalar(p, q.x(), q.y(), q.z(), &u, &v)) return false;
  *pixel = {u, v};
  return true;
}

}  // namespace lt

// The starting point of a camera calibration (pipeline/calib_camera_start.h):
// homographies, Zhang's closed form, and the equidistant start of a fisheye.
#include "pipeline/calib_camera_start.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace lt {

namespace {

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

}  // namespace

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

Pose PoseFromHomography(const Eigen::Matrix3d& camera_matrix, const Eigen::Matrix3d& homography) {
  Eigen::Matrix3d a = camera_matrix.inverse() * homography;
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

// The start of a fisheye calibration: Zhang's closed form on distorted pixels
// fails for a wide lens (a board spanning 90° of the field is no homography
// of the plane), so the lens is first taken as equidistant about the image
// centre, the sensor's Kannala–Brandt model with k1..k4 = 0. Its focal length is the
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
  const double cos_max = std::cos(80.0 * M_PI / 180.0);  // rays beyond 80° are left out (their tangent runs away)
  auto fit = [&](double f, std::vector<Eigen::Matrix3d>* hs) {
    CameraParams equidistant;  // Kannala–Brandt with k1..k4 = 0: r = f θ
    equidistant.width = width, equidistant.height = height;
    equidistant.fx = equidistant.fy = f;
    equidistant.cx = centre.x(), equidistant.cy = centre.y();
    equidistant.distortion = DistortionModel::kFisheye;
    const Camera lens(equidistant);
    double sum2 = 0;
    size_t n = 0;
    if (hs) hs->clear();
    for (const CalibrationView& view : views) {
      // The corners lifted to the pinhole plane z = 1.
      std::vector<Eigen::Vector2d> from, to, seen;
      for (size_t i = 0; i < view.pixels.size(); ++i) {
        const std::optional<Eigen::Vector3d> ray = lens.Unproject(view.pixels[i]);
        if (!ray || !(ray->z() > cos_max)) continue;
        from.push_back(view.target_points[i].head<2>());
        to.push_back(ray->head<2>() / ray->z());
        seen.push_back(view.pixels[i]);
      }
      Eigen::Matrix3d h;
      if (from.size() < 4 || !EstimateHomography(from, to, &h)) return std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < from.size(); ++i) {
        const Eigen::Vector3d q = h * from[i].homogeneous();
        const std::optional<Eigen::Vector2d> px = q.z() > 0 ? lens.Project(q / q.z()) : std::nullopt;
        if (!px) return std::numeric_limits<double>::infinity();
        sum2 += (*px - seen[i]).squaredNorm();
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

}  // namespace lt

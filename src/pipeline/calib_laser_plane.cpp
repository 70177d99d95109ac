#include "pipeline/calib_laser_plane.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/error.h"
#include "pipeline/option_checks.h"
#include "core/random.h"

namespace lt {

namespace {

// Total least squares: the plane through the centroid normal to the direction
// of least spread. Eigenvalues of the scatter matrix ascending.
struct TlsFit {
  Plane plane;
  Eigen::Vector3d centroid;
  Eigen::Vector3d eigenvalues;  // ascending
  Eigen::Matrix3d axes;         // columns: eigenvectors, ascending
};

TlsFit FitTls(const std::vector<Eigen::Vector3d>& pts, const std::vector<int>& idx) {
  TlsFit f;
  f.centroid.setZero();
  for (int i : idx) f.centroid += pts[size_t(i)];
  f.centroid /= double(idx.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i : idx) {
    const Eigen::Vector3d q = pts[size_t(i)] - f.centroid;
    scatter += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  f.eigenvalues = eig.eigenvalues().cwiseMax(0.0);
  f.axes = eig.eigenvectors();
  f.plane = Plane::FromPointNormal(f.centroid, f.axes.col(0));
  return f;
}

std::vector<int> Inliers(const std::vector<Eigen::Vector3d>& pts, const Plane& plane, double threshold) {
  std::vector<int> in;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (std::abs(plane.SignedDistance(pts[i])) <= threshold) in.push_back(int(i));
  }
  return in;
}

constexpr uint64_t kRansacPurpose = 0x6c61736572ull;  // "laser"

}  // namespace

void LaserPlaneFitOptions::Check() const {
  Require(std::isfinite(inlier_threshold_m) && inlier_threshold_m > 0, "inlier_threshold_m",
          "must be > 0, got " + FormatNumber(inlier_threshold_m));
  Require(confidence > 0 && confidence < 1, "confidence", "must be in (0, 1), got " + FormatNumber(confidence));
  Require(max_iterations >= 1, "max_iterations", "must be >= 1, got " + std::to_string(max_iterations));
  Require(min_inlier_fraction >= 0 && min_inlier_fraction <= 1, "min_inlier_fraction",
          "must be in [0, 1], got " + FormatNumber(min_inlier_fraction));
  Require(min_points >= 4, "min_points", "must be >= 4, got " + std::to_string(min_points));
  Require(min_spread_ratio >= 0 && min_spread_ratio < 1, "min_spread_ratio",
          "must be in [0, 1), got " + FormatNumber(min_spread_ratio));
  Require(min_target_angle_deg >= 0 && min_target_angle_deg < 90, "min_target_angle_deg",
          "must be in [0, 90), got " + FormatNumber(min_target_angle_deg));
}

std::vector<LaserPoint> StripePointsOnTarget(const Camera& camera, const std::vector<LaserTargetView>& views,
                                             int* skipped) {
  std::vector<LaserPoint> out;
  int missed = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    const auto& view = views[v];
    if (!view.plane_ids.empty() && view.plane_ids.size() != view.stripe_pixels.size()) {
      throw InputError("", "view " + std::to_string(v) + ": " + std::to_string(view.plane_ids.size()) +
                               " plane ids for " + std::to_string(view.stripe_pixels.size()) + " stripe pixels");
    }
    const Plane target = Plane{Eigen::Vector3d::UnitZ(), 0.0}.Transformed(view.cam_from_target);
    for (size_t k = 0; k < view.stripe_pixels.size(); ++k) {
      const int id = view.plane_ids.empty() ? 0 : view.plane_ids[k];
      if (id < 0) throw InputError("", "view " + std::to_string(v) + ": negative plane id " + std::to_string(id));
      const auto ray = camera.Unproject(view.stripe_pixels[k]);
      const auto t = ray ? target.IntersectRay(Eigen::Vector3d::Zero(), *ray) : std::nullopt;
      if (!t) {
        ++missed;
        continue;
      }
      out.push_back({*t * *ray, id, int(v)});
    }
  }
  if (skipped) *skipped = missed;
  return out;
}

LaserPlaneFit FitLaserPlane(const std::vector<Eigen::Vector3d>& pts, const LaserPlaneFitOptions& options,
                            int plane_id) {
  options.Check();
  LaserPlaneFit fit;
  fit.plane_id = plane_id;
  fit.points = int(pts.size());
  const std::string name = "laser plane " + std::to_string(plane_id);
  auto refuse = [&](const std::string& reason) {
    fit.ok = false;
    fit.reason = name + ": " + reason;
    return fit;
  };
  for (const auto& p : pts) {
    if (!p.allFinite()) return refuse("a point is not finite");
  }
  if (fit.points < options.min_points) {
    return refuse("too few points: " + std::to_string(fit.points) + " (at least " + std::to_string(options.min_points) +
                  ")");
  }

  // ---- RANSAC
  Rng rng = Rng::For(options.seed, 0, uint64_t(plane_id), 0, kRansacPurpose);
  const int n = fit.points;
  int best_count = 0;
  Plane best;
  double needed = double(options.max_iterations);
  int degenerate_samples = 0;
  for (fit.ransac_iterations = 0; fit.ransac_iterations < std::min(double(options.max_iterations), needed);
       ++fit.ransac_iterations) {
    int a = int(rng.NextU32() % uint32_t(n)), b = int(rng.NextU32() % uint32_t(n)), c = int(rng.NextU32() % uint32_t(n));
    const Eigen::Vector3d u = pts[size_t(b)] - pts[size_t(a)], w = pts[size_t(c)] - pts[size_t(a)];
    const Eigen::Vector3d normal = u.cross(w);
    // Skip repeated or (nearly) collinear samples: sin(angle) below 1e-6.
    if (!(normal.norm() > 1e-6 * u.norm() * w.norm())) {
      ++degenerate_samples;
      continue;
    }
    const Plane plane = Plane::FromPointNormal(pts[size_t(a)], normal);
    int count = 0;
    for (const auto& p : pts) count += std::abs(plane.SignedDistance(p)) <= options.inlier_threshold_m;
    if (count > best_count) {
      best_count = count;
      best = plane;
      const double w3 = std::pow(double(count) / n, 3);
      needed = w3 >= 1 ? 1 : std::log(1 - options.confidence) / std::log(1 - w3);
    }
  }
  if (best_count < 3) {
    return refuse(degenerate_samples == fit.ransac_iterations
                      ? std::string("the points are collinear (every sample of three was degenerate)")
                      : std::string("no plane found"));
  }

  // ---- total least squares on the inliers, re-selected until stable
  std::vector<int> in = Inliers(pts, best, options.inlier_threshold_m);
  TlsFit tls;
  for (int round = 0; round < 10; ++round) {
    if (in.size() < 3) break;
    tls = FitTls(pts, in);
    std::vector<int> next = Inliers(pts, tls.plane, options.inlier_threshold_m);
    if (next == in) break;
    in = std::move(next);
  }
  fit.inliers = int(in.size());
  if (fit.inliers < options.min_points || fit.inliers < options.min_inlier_fraction * n) {
    return refuse("too few inliers: " + std::to_string(fit.inliers) + " of " + std::to_string(n) + " points within " +
                  Fmt(options.inlier_threshold_m * 1e3) + " mm of the best plane");
  }
  tls = FitTls(pts, in);
  const double N = double(fit.inliers);
  fit.centroid = tls.centroid;
  fit.spread_m = Eigen::Vector3d(std::sqrt(tls.eigenvalues[2] / N), std::sqrt(tls.eigenvalues[1] / N),
                                 std::sqrt(tls.eigenvalues[0] / N));
  fit.plane = tls.plane;
  if (fit.plane.d > 0) fit.plane = {-fit.plane.n, -fit.plane.d};
  double ss = 0;
  for (int i : in) ss += std::pow(fit.plane.SignedDistance(pts[size_t(i)]), 2);
  fit.residual_rms_m = std::sqrt(ss / N);
  if (!(fit.spread_m[1] > options.min_spread_ratio * fit.spread_m[0])) {
    return refuse("the points are nearly collinear (principal spreads " + Fmt(fit.spread_m[0] * 1e3) + " mm and " +
                  Fmt(fit.spread_m[1] * 1e3) +
                  " mm): the target views lie in nearly the same plane; tilt or move the target between views");
  }
  // Covariance of the TLS plane (residuals r = w − a·v + b·u − δ in the
  // principal frame: a tilt about each in-plane axis and a shift along n).
  const double sigma2 = fit.inliers > 3 ? ss / (N - 3) : 0.0;
  const double var_mid = sigma2 / tls.eigenvalues[1], var_max = sigma2 / tls.eigenvalues[2];
  fit.normal_std_rad = std::sqrt(var_mid + var_max);
  const double c_mid = tls.axes.col(1).dot(fit.centroid), c_max = tls.axes.col(2).dot(fit.centroid);
  fit.offset_std_m = std::sqrt(sigma2 / N + c_mid * c_mid * var_mid + c_max * c_max * var_max);
  fit.ok = true;
  return fit;
}

std::vector<LaserPlaneFit> FitLaserPlanes(const std::vector<LaserPoint>& points, const LaserPlaneFitOptions& options) {
  options.Check();
  std::map<int, std::vector<Eigen::Vector3d>> groups;
  for (const auto& p : points) groups[p.plane_id].push_back(p.p_in_cam);
  std::vector<LaserPlaneFit> fits;
  for (const auto& [id, pts] : groups) fits.push_back(FitLaserPlane(pts, options, id));
  return fits;
}

std::vector<LaserPlaneFit> CalibrateLaserPlanes(const Camera& camera, const std::vector<LaserTargetView>& views,
                                                const LaserPlaneFitOptions& options, int* skipped) {
  options.Check();
  const std::vector<LaserPoint> points = StripePointsOnTarget(camera, views, skipped);
  std::vector<LaserPlaneFit> fits = FitLaserPlanes(points, options);
  const double min_sin = std::sin(options.min_target_angle_deg * M_PI / 180.0);
  for (auto& fit : fits) {
    if (!fit.ok) continue;
    std::vector<int> inliers_per_view(views.size(), 0);
    for (const auto& p : points) {
      if (p.plane_id == fit.plane_id && std::abs(fit.plane.SignedDistance(p.p_in_cam)) <= options.inlier_threshold_m) {
        ++inliers_per_view[size_t(p.view)];
      }
    }
    const std::string name = "laser plane " + std::to_string(fit.plane_id) + ": ";
    int views_used = 0;
    for (size_t v = 0; v < views.size(); ++v) {
      if (inliers_per_view[v] == 0) continue;
      ++views_used;
      const Eigen::Vector3d target_n = views[v].cam_from_target.linear().col(2);
      const double s = fit.plane.n.cross(target_n).norm();
      if (!(s >= min_sin)) {
        fit.ok = false;
        fit.reason = name + "the fitted plane lies within " + Fmt(std::asin(std::min(s, 1.0)) * 180 / M_PI) +
                     " degrees of the target plane of view " + std::to_string(v) +
                     " (at least " + Fmt(options.min_target_angle_deg) +
                     " are needed): the points do not come from the laser sheet crossing the targets";
        break;
      }
    }
    if (fit.ok && views_used < 2) {
      fit.ok = false;
      fit.reason = name + "the inliers come from " + std::to_string(views_used) + " view (at least 2 are needed)";
    }
  }
  return fits;
}

PlaneError ComparePlanes(const Plane& estimate, const Plane& truth) {
  const double s = estimate.n.dot(truth.n) < 0 ? -1.0 : 1.0;
  const double c = std::clamp(s * estimate.n.dot(truth.n), -1.0, 1.0);
  // acos loses precision near 1: use the cross product for small angles.
  const double angle = std::atan2(estimate.n.cross(truth.n).norm(), c);
  return {angle, std::abs(s * estimate.d - truth.d)};
}

}  // namespace lt

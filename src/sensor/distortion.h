// Lens distortion models in OpenCV's conventions, with exact inverses.
//
// Coordinates: a ray (X, Y, Z) in the camera frame; "distorted normalised"
// coordinates t = ((u - cx)/fx, (v - cy)/fy) of a pixel (u, v).
//   none           t = (X/Z, Y/Z)                                  (Z > 0)
//   brown_conrady  x = (X/Z, Y/Z), r² = |x|², t = D(x):            (Z > 0)
//                  t_x = x(1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x y + p2 (r² + 2x²)
//                  t_y = y(1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2y²) + 2 p2 x y
//   fisheye        θ = angle between the ray and +Z (0..π), φ its azimuth,
//                  θ_d = θ (1 + k1 θ² + k2 θ⁴ + k3 θ⁶ + k4 θ⁸), t = θ_d (cos φ, sin φ)
//                  (OpenCV's cv::fisheye for Z > 0, extended beyond 90°: the
//                  inverse works in angle, so rays with Z <= 0 come back as such.)
//
// Valid domain. A distortion is only invertible where it does not fold. For
// Brown–Conrady the domain is star-shaped around the axis: along each of 512
// radial directions (interpolated between them) it reaches from 0 to the first
// radius where det(∂t/∂x) <= 0 (a fold), or to where the image of the ray lies 4
// times as far from the principal point as the farthest image corner (beyond
// that the model is not examined); a point must also have det(∂t/∂x) > 0 itself. For the fisheye it is
// θ up to the first zero of dθ_d/dθ, or up to π. Construction rejects a
// distortion whose fold lies inside the image (ParamError on "distortion").
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace lt {

enum class DistortionModel { kNone, kBrownConrady, kFisheye };

// "none", "brown_conrady", "fisheye".
const char* DistortionModelName(DistortionModel m);

// The rectangle covered by the image in distorted normalised coordinates
// (pixel edges: u in [-0.5, width - 0.5]), and the pixel scale for tolerances.
struct ImageBounds {
  double x_min = -1, x_max = 1, y_min = -1, y_max = 1;
  double fx = 1, fy = 1, cx = 0, cy = 0;
  bool Contains(const Eigen::Vector2d& t) const {
    return t.x() >= x_min && t.x() <= x_max && t.y() >= y_min && t.y() <= y_max;
  }
};

// Brown–Conrady coefficients, OpenCV order k1 k2 p1 p2 k3.
struct BrownConradyCoeffs {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  bool IsZero() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }
  // t = D(x); optional analytic Jacobian ∂t/∂x.
  Eigen::Vector2d Distort(const Eigen::Vector2d& x, Eigen::Matrix2d* jacobian = nullptr) const;
};

// OpenCV's distCoeffs for the pinhole model as calibrateCamera, ROS camera_info and
// other tools write them: 4 (k1 k2 p1 p2, k3 = 0), 5, 8, 12 or 14 elements. The terms
// past k3 (the rational model's k4 k5 k6, thin prism s1..s4, tilt tauX tauY) are not
// modelled and must be 0. On success fills *c and returns an empty problem; otherwise
// `problem` says why and `element` names the offending element (0-based; -1: the length).
struct OpenCvDistCoeffsProblem {
  int element = -1;
  std::string problem;
  bool ok() const { return problem.empty(); }
};
OpenCvDistCoeffsProblem BrownConradyFromOpenCv(const std::vector<double>& d, BrownConradyCoeffs* c);

// Kannala–Brandt coefficients, OpenCV fisheye order k1 k2 k3 k4.
struct KannalaBrandtCoeffs {
  double k1 = 0, k2 = 0, k3 = 0, k4 = 0;
  // θ_d(θ); optional derivative dθ_d/dθ.
  double ThetaD(double theta, double* derivative = nullptr) const;
};

// One camera's distortion: the model, its coefficients and its valid domain.
class LensDistortion {
 public:
  LensDistortion() = default;  // no distortion
  // Throws ParamError("distortion", ...) when the distortion folds within `bounds`
  // or some pixel of the image border has no valid ray.
  static LensDistortion BrownConrady(const BrownConradyCoeffs& c, const ImageBounds& bounds);
  static LensDistortion Fisheye(const KannalaBrandtCoeffs& c, const ImageBounds& bounds);

  DistortionModel model() const { return model_; }
  const BrownConradyCoeffs& brown_conrady() const { return bc_; }
  const KannalaBrandtCoeffs& fisheye() const { return kb_; }
  // Largest angle from the optical axis inside the fisheye's domain (π without a fold).
  double fisheye_theta_max() const { return theta_max_; }

  // Ray (any length) -> distorted normalised coordinates; nullopt outside the domain.
  std::optional<Eigen::Vector2d> Distort(const Eigen::Vector3d& ray) const;
  // Distorted normalised coordinates -> unit ray; nullopt when no ray of the
  // domain maps there to 1e-9 px.
  std::optional<Eigen::Vector3d> Undistort(const Eigen::Vector2d& t) const;
  // dΩ/dA: solid angle per unit area of distorted normalised coordinates at t
  // (divide by fx·fy for sr per pixel²). 0 when t has no valid ray.
  double SolidAngleDensity(const Eigen::Vector2d& t) const;

 private:
  // Brown–Conrady helpers.
  double DomainRadius(double phi) const;
  bool InBcDomain(const Eigen::Vector2d& x) const;
  std::optional<Eigen::Vector2d> UndistortBc(const Eigen::Vector2d& t) const;
  bool NewtonBc(const Eigen::Vector2d& t, Eigen::Vector2d* x, int max_iterations) const;
  // Fisheye helper: θ for θ_d (θ_d <= theta_d_max_).
  double SolveTheta(double theta_d) const;
  void CheckBorder(const ImageBounds& bounds) const;

  DistortionModel model_ = DistortionModel::kNone;
  BrownConradyCoeffs bc_;
  KannalaBrandtCoeffs kb_;
  double pixel_scale_ = 1.0;          // max(fx, fy): normalised -> pixel tolerance
  std::vector<double> domain_radius_;  // Brown–Conrady: per direction (kDirections)
  double theta_max_ = M_PI;            // fisheye
  double theta_d_max_ = M_PI;          // fisheye: θ_d(theta_max_)
  bool fisheye_folds_ = false;
};

}  // namespace lt

// Burley's normalized diffusion profile (Christensen & Burley 2015,
// "Approximate Reflectance Profiles for Efficient Subsurface Scattering",
// Pixar technical memo 15-04): the diffuse reflectance a point of light
// produces at distance r on a flat surface of translucent material, such as
// the laser stripe spreading into 3D-printed PLA.
//
//   R(r) = A (exp(-r/d) + exp(-r/(3d))) / (8 pi d r)        [1/m^2]
//   integral of R over the plane = A (total diffuse reflectance, surface albedo)
//   d = l / s(A): l the mean free path, s the paper's searched fit (below)
//
// The radial CDF has an exact inverse (a cubic in exp(-r/(3d))), and the
// profile across an infinitely long thin line of light (the line-spread
// function) has a closed form in the modified Bessel function K0:
//   LSF(x) = integral over y of R(sqrt(x^2 + y^2)) dy
//          = A (K0(|x|/d) + K0(|x|/(3d))) / (4 pi d)   [1/m]
// Derivations: docs/rendering.md, "Subsurface diffusion profile".
// Double precision: these feed sampling radii and reference curves, not hot loops.
#pragma once

#include <string>

namespace lt {

// Which of the paper's fits of the shape factor s = l/d to use (section 5):
enum class DiffusionFit {
  // Perpendicular ("searchlight") illumination, l = volume mean free path:
  //   s = 1.85 - A + 7 |A - 0.8|^3.  The default: a laser hits the surface as a beam.
  kPerpendicularMeanFreePath,
  // Diffuse surface transmission, l = volume mean free path:
  //   s = 1.9 - A + 3.5 (A - 0.8)^2.
  kDiffuseTransmissionMeanFreePath,
  // Perpendicular illumination, l = diffuse mean free path on the surface:
  //   s = 3.5 + 100 (A - 0.33)^4.
  kPerpendicularDiffuseMeanFreePath,
};

// s(A) of a fit (dimensionless).
double BurleyShapeFactor(double albedo, DiffusionFit fit);

struct DiffusionProfileParams {
  double albedo = 0.8;            // A, total diffuse reflectance in [0, 1]
  double mean_free_path = 1e-3;   // l [m], > 0
  DiffusionFit fit = DiffusionFit::kPerpendicularMeanFreePath;

  // Throws lt::InputError(where, ...) when a value is out of range or not finite.
  void Check(const std::string& where) const;
};

class BurleyProfile {
 public:
  explicit BurleyProfile(const DiffusionProfileParams& params);
  // Directly from A and the shape distance d [m].
  static BurleyProfile FromShapeDistance(double albedo, double d);

  double albedo() const { return albedo_; }
  double d() const { return d_; }

  // R(r) [1/m^2]. R diverges like 1/r at 0 (integrably); r is clamped to
  // >= kMinRadiusFraction * d so that the value stays finite.
  double Evaluate(double r) const;
  // Fraction of the reflected light within radius r:
  // CDF(r) = 1 - exp(-r/d)/4 - 3 exp(-r/(3d))/4.
  double Cdf(double r) const;
  // Density of the sampled radius, 2 pi r R(r) / A [1/m] (finite at r = 0: 1/(2d)).
  double RadialPdf(double r) const;
  // Exact inverse of Cdf for u in [0, 1): with y = exp(-r/(3d)), the CDF is the
  // cubic y^3 + 3y = 4(1 - u), whose real root is y = 2 sinh(asinh(2(1 - u))/3).
  // u >= 1 is clamped to the largest double below 1.
  double SampleRadius(double u) const;
  // SampleRadius(u) = -3 d log y(u) in two steps, log y(u) depending on u
  // alone: a caller that asks for one u at every point takes its LogRoot once.
  static double LogRoot(double u);
  double RadiusOfLogRoot(double log_root) const;
  // LSF(x) [1/m] in closed form (K0); |x| clamped like r in Evaluate.
  double LineSpread(double x) const;
  // The line-spread function convolved with a Gaussian of standard deviation
  // sigma [m] across the line (a laser stripe of Gaussian cross-section):
  // integral of LSF(s) N(x - s; 0, sigma) ds, by the trapezoid rule in log(s)
  // (the log singularity of LSF at 0 then decays exponentially), with the
  // analytic integral of the singularity below 1e-6 min(d, sigma). Relative
  // accuracy better than 1e-8. sigma = 0 returns LineSpread(x).
  double LineSpreadGaussian(double x, double sigma) const;

  static constexpr double kMinRadiusFraction = 1e-9;

 private:
  BurleyProfile(double albedo, double d) : albedo_(albedo), d_(d) {}
  double albedo_;
  double d_;
};

}  // namespace lt

// A laser line projector as an analytic emitter: a point source whose radiant
// intensity I(direction) (W/sr) is a fan along each sheet times a Gaussian across
// it, normalised so that ∫ I dΩ over the sphere equals the configured power.
//
// Projector frame: the beam leaves the origin along +z; a sheet spans the x–z
// plane, so its fan opens along x and its thickness is across y. A diffractive
// element makes N sheets, sheet k tilted about the x axis by angle α_k (toward
// +y for α_k > 0): its central ray is (0, sin α_k, cos α_k) and its plane has
// normal (0, cos α_k, −sin α_k) through the origin.
//
// For a direction ω, sheet k has the along-fan angle φ = atan2(ω·x, ω·c_k)
// (c_k its central ray) and the out-of-plane angle ψ = asin(ω·n_k). In these
// coordinates dΩ = cos ψ dψ dφ, and
//   I_k(ω) = P_k · F(φ) · G(ψ)
//   F: flat-top 1/Φ for |φ| <= Φ/2 (Φ the fan angle), or a Gaussian with
//      1/e² full width Φ (σ_φ = Φ/4), normalised over φ in (−π, π];
//   G: exp(−ψ²/(2σ²)) / (σ √(2π) e^{−σ²/2}), the exact normaliser of
//      ∫ G cos ψ dψ = 1 (σ <= 10°, so the tail beyond ±90° is below 1e-17);
//      σ = divergence/4 (divergence: 1/e² full angle), or for a Gaussian beam
//      σ(r) = w(r)/(2r) with w(r) = w0 √(1 + ((r − z_w)/z_R)²), capped at 10°,
//      so the line thickness changes with the distance r from the projector.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/pose.h"
#include "sensor/plane.h"

namespace lt {

enum class FanProfile { kFlatTop, kGaussian };

struct GaussianBeam {
  double waist_m = 50e-6;            // w0: 1/e² radius of the line's thickness at the waist
  double rayleigh_range_m = 12e-3;   // z_R
  double waist_distance_m = 0.0;     // z_w: distance of the waist from the projector
};

struct LaserParams {
  double power_w = 5e-3;
  double wavelength_m = 650e-9;
  Pose cam_from_projector = Pose::Identity();
  FanProfile fan_profile = FanProfile::kFlatTop;
  double fan_angle_rad = 60.0 * M_PI / 180.0;  // (0, 2π]
  double divergence_rad = 2e-3;               // 1/e² full angle across the sheet, (0, 40°]
  std::optional<GaussianBeam> gaussian_beam;  // when set, replaces divergence_rad
  std::vector<double> sheet_angles_rad = {0.0};  // one per sheet, in (-90°, 90°), increasing
  std::vector<double> sheet_power;  // relative power per sheet (normalised to sum 1); empty: equal

  // Throws ParamError naming the key.
  void Check() const;
};

// Sheet angles of a diffractive element: n sheets, equal angular spacing, centred on 0.
std::vector<double> EvenSheetAngles(int n, double spacing_rad);

class LaserProjector {
 public:
  static constexpr double kMaxSigmaRad = 10.0 * M_PI / 180.0;
  static constexpr double kDefaultCutoffSigma = 8.0;

  LaserProjector() : LaserProjector(LaserParams{}) {}
  explicit LaserProjector(const LaserParams& params);  // checks params (ParamError)

  const LaserParams& params() const { return params_; }
  double power_w() const { return params_.power_w; }
  double wavelength_m() const { return params_.wavelength_m; }
  const Pose& cam_from_projector() const { return params_.cam_from_projector; }
  Pose projector_from_cam() const { return params_.cam_from_projector.inverse(); }
  Eigen::Vector3d origin_in_cam() const { return params_.cam_from_projector.translation(); }
  int sheet_count() const { return int(params_.sheet_angles_rad.size()); }
  double sheet_power_w(int sheet) const { return sheet_power_w_.at(size_t(sheet)); }
  // Central ray of a sheet, projector frame.
  Eigen::Vector3d SheetDirection(int sheet) const;

  // Far-field radiant intensity (W/sr) toward a direction in the projector frame
  // (any length), summed over sheets, and one sheet's share.
  double RadiantIntensity(const Eigen::Vector3d& dir_in_projector) const;
  double SheetIntensity(int sheet, const Eigen::Vector3d& dir_in_projector) const;
  // Intensity toward a point (projector frame), with the thickness at its
  // distance for a Gaussian beam; equals RadiantIntensity otherwise.
  double RadiantIntensityAt(const Eigen::Vector3d& p_in_projector) const;
  double SheetIntensityAt(int sheet, const Eigen::Vector3d& p_in_projector) const;
  // Irradiance (W/m²) on a surface at p with unit normal n, both in the camera
  // frame: I · max(0, n·(o − p)/|o − p|) / |o − p|² (no occlusion test).
  double IrradianceAt(const Eigen::Vector3d& p_in_cam, const Eigen::Vector3d& normal_in_cam) const;

  // Angular σ (radians) across the sheets at distance r (infinity: far field).
  double SheetSigma(double distance_m) const;
  // Out-of-plane angle ψ of a direction relative to a sheet (radians, signed).
  double SheetOffsetAngle(int sheet, const Eigen::Vector3d& dir_in_projector) const;
  // False when p (projector frame) cannot receive meaningful light: for every
  // sheet it lies more than k_sigma σ out of the plane or outside the fan
  // (flat-top) or more than k_sigma σ_φ along it (Gaussian). At 8σ the
  // intensity is below e^-32 ≈ 1e-14 of the peak.
  bool MayIlluminate(const Eigen::Vector3d& p_in_projector, double k_sigma = kDefaultCutoffSigma) const;
  // The fan angle |phi| beyond which the sheets carry no meaningful light: half
  // the fan (flat-top) or k_sigma sigma_phi (Gaussian).
  double FanHalfWidth(double k_sigma = kDefaultCutoffSigma) const;

  // The plane of a sheet in the camera frame (n·p + d = 0): the ground-truth
  // laser calibration. And in the projector frame (through the origin).
  Plane SheetPlane(int sheet) const;
  Plane SheetPlaneInProjector(int sheet) const;

  // A direction's along-fan angle phi and out-of-plane angle psi relative to a
  // sheet (projector frame, unit direction), and back.
  struct SheetAngles {
    double phi, psi;
  };
  SheetAngles Angles(int sheet, const Eigen::Vector3d& unit_dir) const;
  Eigen::Vector3d DirectionAt(int sheet, double phi, double psi) const;
  // Each of the two angles alone (the same values as Angles).
  double Phi(int sheet, const Eigen::Vector3d& unit_dir) const;
  double Psi(int sheet, const Eigen::Vector3d& unit_dir) const;

 private:
  double Fan(double phi) const;
  double Across(double psi, double sigma) const;

  LaserParams params_;
  std::vector<double> sheet_power_w_;
  std::vector<Eigen::Vector3d> sheet_center_;  // c_k
  std::vector<Eigen::Vector3d> sheet_normal_;  // n_k
  double fan_norm_ = 1.0;                      // 1/∫ of the unnormalised fan profile
};

}  // namespace lt

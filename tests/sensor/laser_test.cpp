// Laser projector: the emitter integrates to its power, profiles match their
// closed forms, and the sheet planes are the ground-truth calibration.
#include "sensor/laser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "sensor/param_error.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180;

// ∫ f dΩ over the sphere by the midpoint rule in spherical coordinates whose
// polar axis is the projector's x axis (β from +x, γ around it), so every sheet
// plane — they all contain the x axis — is a line γ = const in this grid.
// The midpoint rule is spectrally accurate for a smooth Gaussian sampled at
// σ/2 (error ~exp(-2π²·4) relative); the flat-top fan's edges (at β = 90° ± Φ/2)
// cost at most half a 0.25° cell each, ~0.2% of a 70° fan, hence the 0.5% tolerance.
double IntegrateSphere(const std::function<double(const Eigen::Vector3d&)>& f, int n_beta, int n_gamma) {
  double sum = 0;
  const double db = M_PI / n_beta, dg = 2 * M_PI / n_gamma;
  for (int i = 0; i < n_beta; ++i) {
    double b = (i + 0.5) * db, sb = std::sin(b), cb = std::cos(b);
    double row = 0;
    for (int j = 0; j < n_gamma; ++j) {
      double g = (j + 0.5) * dg;
      row += f(Eigen::Vector3d(cb, sb * std::cos(g), sb * std::sin(g)));
    }
    sum += row * sb * db * dg;
  }
  return sum;
}

LaserParams Broad() {
  LaserParams p;
  p.power_w = 7e-3;
  p.fan_angle_rad = 70 * kDeg;
  p.divergence_rad = 8 * kDeg;  // σ = 2°, sampled every 1° across by the grid below
  return p;
}

TEST(Laser, FlatTopSheetIntegratesToPower) {
  LaserProjector laser(Broad());
  double total = IntegrateSphere([&](const Eigen::Vector3d& d) { return laser.RadiantIntensity(d); }, 720, 360);
  EXPECT_NEAR(total, 7e-3, 0.005 * 7e-3);
}

TEST(Laser, DiffractiveSheetsWithGaussianFanIntegrateToPower) {
  LaserParams p = Broad();
  p.fan_profile = FanProfile::kGaussian;
  p.sheet_angles_rad = EvenSheetAngles(3, 15 * kDeg);
  p.sheet_power = {1.0, 2.0, 0.5};
  LaserProjector laser(p);
  double total = IntegrateSphere([&](const Eigen::Vector3d& d) { return laser.RadiantIntensity(d); }, 720, 360);
  EXPECT_NEAR(total, 7e-3, 0.005 * 7e-3);
  double sheet1 = IntegrateSphere([&](const Eigen::Vector3d& d) { return laser.SheetIntensity(1, d); }, 720, 360);
  EXPECT_NEAR(sheet1, 7e-3 * 2.0 / 3.5, 0.005 * 7e-3 * 2.0 / 3.5);
  EXPECT_NEAR(laser.sheet_power_w(1), 4e-3, 1e-15);
}

TEST(Laser, GaussianBeamIntegratesToPowerAtEveryDistance) {
  LaserParams p = Broad();
  p.gaussian_beam = GaussianBeam{0.5e-3, 5e-3, 1e-3};  // far-field σ = w0/(2 z_R) = 2.9°
  LaserProjector laser(p);
  for (double r : {0.5e-3, 3e-3, 0.05}) {
    double total =
        IntegrateSphere([&](const Eigen::Vector3d& d) { return laser.RadiantIntensityAt(d * r); }, 720, 360);
    EXPECT_NEAR(total, 7e-3, 0.005 * 7e-3) << r;
  }
}

TEST(Laser, PeakIntensityAndProfilesMatchClosedForms) {
  LaserParams p = Broad();
  p.divergence_rad = 0.2 * kDeg;
  LaserProjector laser(p);
  double sigma = p.divergence_rad / 4;
  double peak = p.power_w / p.fan_angle_rad / (sigma * std::sqrt(2 * M_PI) * std::exp(-sigma * sigma / 2));
  EXPECT_NEAR(laser.RadiantIntensity(Eigen::Vector3d::UnitZ()), peak, 1e-12 * peak);
  // Flat along the fan, zero beyond its edge.
  Eigen::Vector3d in_fan(std::sin(34 * kDeg), 0, std::cos(34 * kDeg));
  Eigen::Vector3d out_fan(std::sin(36 * kDeg), 0, std::cos(36 * kDeg));
  EXPECT_NEAR(laser.RadiantIntensity(in_fan), peak, 1e-12 * peak);
  EXPECT_EQ(laser.RadiantIntensity(out_fan), 0.0);
  // Across: 1/e² at half the divergence.
  double half = p.divergence_rad / 2;
  Eigen::Vector3d edge(0, std::sin(half), std::cos(half));
  EXPECT_NEAR(laser.RadiantIntensity(edge) / peak, std::exp(-2.0), 1e-9);

  LaserParams g = p;
  g.fan_profile = FanProfile::kGaussian;
  LaserProjector gauss(g);
  Eigen::Vector3d fan_edge(std::sin(35 * kDeg), 0, std::cos(35 * kDeg));
  EXPECT_NEAR(gauss.RadiantIntensity(fan_edge) / gauss.RadiantIntensity(Eigen::Vector3d::UnitZ()), std::exp(-2.0), 1e-9);
}

TEST(Laser, GaussianBeamThicknessChangesWithDistance) {
  LaserParams p = Broad();
  const double w0 = 40e-6, zr = 8e-3, zw = 0.1;
  p.gaussian_beam = GaussianBeam{w0, zr, zw};
  LaserProjector laser(p);
  for (double r : {0.05, 0.1, 0.2}) {
    double w = w0 * std::sqrt(1 + std::pow((r - zw) / zr, 2));
    EXPECT_NEAR(laser.SheetSigma(r), w / (2 * r), 1e-15);
    // At the 1/e² radius w across the sheet the intensity is e^-2 of the centre.
    double psi = std::asin(w / r);
    double ratio = laser.RadiantIntensityAt(r * Eigen::Vector3d(0, std::sin(psi), std::cos(psi))) /
                   laser.RadiantIntensityAt(r * Eigen::Vector3d::UnitZ());
    EXPECT_NEAR(ratio, std::exp(-2.0), 1e-3) << r;  // asin(w/r) vs w/r: relative 1e-7 in ψ
  }
  EXPECT_NEAR(laser.SheetSigma(INFINITY), w0 / (2 * zr), 1e-15);
  EXPECT_LT(laser.SheetSigma(0.1), laser.SheetSigma(0.2));
}

TEST(Laser, SheetPlanesAreTheGroundTruthCalibration) {
  LaserParams p = Broad();
  p.sheet_angles_rad = EvenSheetAngles(5, 3 * kDeg);
  p.cam_from_projector = Pose::Identity();
  p.cam_from_projector.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0.1).normalized())).toRotationMatrix();
  p.cam_from_projector.translation() = Eigen::Vector3d(0.04, -0.01, 0.005);
  LaserProjector laser(p);
  ASSERT_EQ(laser.sheet_count(), 5);
  EXPECT_NEAR(laser.SheetDirection(0).y(), std::sin(-6 * kDeg), 1e-15);
  for (int k = 0; k < 5; ++k) {
    Plane pl = laser.SheetPlane(k);
    EXPECT_NEAR(pl.n.norm(), 1.0, 1e-15);
    EXPECT_NEAR(pl.SignedDistance(laser.origin_in_cam()), 0.0, 1e-15);
    for (double phi : {-30.0, 0.0, 20.0}) {
      // Along the sheet: rotate the central ray toward x inside the sheet plane.
      Eigen::Vector3d c = laser.SheetDirection(k);
      Eigen::Vector3d d = std::cos(phi * kDeg) * c + std::sin(phi * kDeg) * Eigen::Vector3d::UnitX();
      Eigen::Vector3d point_in_cam = p.cam_from_projector * (0.2 * d);
      EXPECT_NEAR(pl.SignedDistance(point_in_cam), 0.0, 1e-14);
      // The intensity of sheet k peaks on its plane.
      Eigen::Vector3d n = laser.SheetPlaneInProjector(k).n;
      EXPECT_GT(laser.SheetIntensity(k, d), laser.SheetIntensity(k, d + 1e-3 * n));
      EXPECT_GT(laser.SheetIntensity(k, d), laser.SheetIntensity(k, d - 1e-3 * n));
    }
  }
}

TEST(Laser, IrradianceFollowsInverseSquareAndCosine) {
  LaserParams p = Broad();
  p.cam_from_projector.translation() = Eigen::Vector3d(0.03, 0, 0);
  LaserProjector laser(p);
  double i0 = laser.RadiantIntensity(Eigen::Vector3d::UnitZ());
  Eigen::Vector3d point(0.03, 0, 0.2);
  EXPECT_NEAR(laser.IrradianceAt(point, Eigen::Vector3d(0, 0, -1)), i0 / 0.04, 1e-12 * i0);
  Eigen::Vector3d tilted(std::sin(0.4), 0, -std::cos(0.4));
  EXPECT_NEAR(laser.IrradianceAt(point, tilted), i0 / 0.04 * std::cos(0.4), 1e-12 * i0);
  EXPECT_EQ(laser.IrradianceAt(point, Eigen::Vector3d(0, 0, 1)), 0.0);  // facing away
}

TEST(Laser, MayIlluminateCutsAtKSigma) {
  LaserParams p = Broad();
  p.divergence_rad = 0.4 * kDeg;
  LaserProjector laser(p);
  double s = laser.SheetSigma(INFINITY);
  auto at = [](double psi) -> Eigen::Vector3d { return Eigen::Vector3d(0, std::sin(psi), std::cos(psi)) * 0.3; };
  EXPECT_TRUE(laser.MayIlluminate(at(0)));
  EXPECT_TRUE(laser.MayIlluminate(at(7.9 * s)));
  EXPECT_FALSE(laser.MayIlluminate(at(8.1 * s)));
  EXPECT_LT(laser.RadiantIntensity(at(8.1 * s)) / laser.RadiantIntensity(at(0)), 1e-14);
  EXPECT_FALSE(laser.MayIlluminate(Eigen::Vector3d(std::sin(40 * kDeg), 0, std::cos(40 * kDeg))));
  EXPECT_FALSE(laser.MayIlluminate(Eigen::Vector3d(0, 0, -1)));
}

TEST(Laser, InvalidParametersNameTheirKey) {
  auto key_of = [](LaserParams p) {
    try {
      LaserProjector l(p);
    } catch (const ParamError& e) {
      return e.key();
    }
    return std::string();
  };
  LaserParams p;
  p.sheet_angles_rad.clear();
  p.sheet_power.clear();
  EXPECT_EQ(key_of(p), "sheet_count");
  p = LaserParams{};
  p.cam_from_projector.linear() *= 1.01;
  EXPECT_EQ(key_of(p), "cam_from_projector");
  p = LaserParams{};
  p.power_w = 0;
  EXPECT_EQ(key_of(p), "power_mw");
  p = LaserParams{};
  p.divergence_rad = 50 * kDeg;
  EXPECT_EQ(key_of(p), "divergence_deg");
}

}  // namespace
}  // namespace lt

// The stress suite's scenes: a camera at the world origin (or anywhere, by a
// pose) looking along +z at a planar surface lit by one laser sheet.
#pragma once

#include <algorithm>
#include <optional>

#include "stress_util.h"

namespace lt::test {

struct PlaneSetup {
  double distance = 0.1;  // D: the surface crosses the optical axis at depth D (m)
  double tilt_rad = 0;    // the surface's normal turned about camera y (0: facing the camera)
  double baseline = 0.03; // laser position along camera x (m)
  double aim_x = 0;       // the sheet meets the axis-parallel line x = aim_x at depth D
  double power_w = 5e-3;
  double divergence_rad = 0.03;  // sigma ~1 px at 0.1 m for the 64x48, fx 150 camera
  double exposure_s = 7e-4;      // peak about 1500 DN of the 2500 DN full well on a facing surface
  Pose world_from_cam = Pose::Identity();
  int width = 64, height = 24;
  double fx = 150;
  DistortionModel distortion = DistortionModel::kNone;
  BrownConradyCoeffs bc;
  int spp = 16;  // 4 x 4 stratified: enough for the pixel integral of a 1 px wide stripe
};

// The surface's plane in the camera frame: through (aim_x, 0, D), normal
// -R_y(tilt) z (facing the camera for |tilt| < 90 degrees).
inline Plane SurfaceInCam(const PlaneSetup& s) {
  Eigen::Vector3d n = -(Eigen::AngleAxisd(s.tilt_rad, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ());
  return Plane::FromPointNormal({s.aim_x, 0, s.distance}, n);
}

// A laser at (baseline, 0, 0) whose sheet spans camera y and contains the
// point (aim_x, 0, D).
inline LaserProjector AimedLaser(const PlaneSetup& s) {
  LaserParams p;
  p.power_w = s.power_w;
  p.wavelength_m = 650e-9;
  double theta = std::atan2(s.baseline - s.aim_x, s.distance);
  Pose cam_from_projector = Pose::Identity();
  cam_from_projector.linear() = (Eigen::AngleAxisd(-theta, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()))
                                    .toRotationMatrix();
  cam_from_projector.translation() = Eigen::Vector3d(s.baseline, 0, 0);
  p.cam_from_projector = cam_from_projector;
  p.fan_angle_rad = 90.0 * M_PI / 180.0;
  p.divergence_rad = s.divergence_rad;
  p.sheet_angles_rad = {0.0};
  p.sheet_power = {1.0};
  return LaserProjector(p);
}

// The rig and settings of a setup, without geometry.
inline void ConfigureRig(const PlaneSetup& s, World* world) {
  SensorRig& rig = world->scene.sensor;
  rig.camera = TestCamera(s.width, s.height, s.fx, s.distortion, s.bc);
  rig.lasers = {AimedLaser(s)};
  ShutterParams sh;
  sh.cycle = {ShutterFrameSpec{"dim", s.exposure_s, true, false, false, std::nullopt}};
  rig.shutter = ShutterSchedule(sh);
  world->scene.motion = StaticMotion{s.world_from_cam};
  world->scene.render.spp = s.spp;
  world->scene.render.max_bounces = 1;
}

// The surface as one rectangle (two triangles), large enough to fill the view.
inline World PlaneWorld(const PlaneSetup& s) {
  World world;
  Eigen::Matrix3d R = Eigen::AngleAxisd(s.tilt_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Eigen::Affine3d world_from_cam(s.world_from_cam.matrix());
  Eigen::Vector3d a = world_from_cam.linear() * (R * Eigen::Vector3d::UnitX());
  Eigen::Vector3d b = world_from_cam.linear() * -Eigen::Vector3d::UnitY();
  Eigen::Vector3d c = world_from_cam * Eigen::Vector3d(s.aim_x, 0, s.distance);
  // Half sizes: the view at depth D is about D * w / fx wide; a grazing surface
  // stretches far along `a`, so 200 D there.
  // Vertices relative to the centre (float), placed by a double transform.
  Eigen::Affine3d world_from_mesh = Eigen::Affine3d::Identity();
  world_from_mesh.translation() = c;
  world.Add(Rectangle(Eigen::Vector3d::Zero(), a, b, 200 * s.distance, 2 * s.distance), world_from_mesh);
  world.Build();
  ConfigureRig(s, &world);
  return world;
}

// The planes of every triangle of instance 0 (the surface), camera frame,
// from the stored float vertices.
inline std::vector<Plane> SurfaceTrianglePlanes(const World& world, const PlaneSetup& s) {
  const SceneInstance& inst = world.geometry->instances[0];
  const Mesh& m = world.geometry->meshes[inst.mesh];
  const Eigen::Affine3d cam_from_mesh = Eigen::Affine3d(s.world_from_cam.inverse().matrix()) * inst.world_from_mesh;
  std::vector<Plane> planes;
  for (size_t t = 0; t < m.TriangleCount(); ++t) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = cam_from_mesh * m.positions[m.indices[3 * t + k]].cast<double>();
    planes.push_back(Plane::FromPointNormal(p[0], (p[1] - p[0]).cross(p[2] - p[0])));
  }
  return planes;
}

// Checks the ground-truth centres against the closed form (relative
// residual <= rel_tol) and that at least `min_centers` exist.
inline void ExpectTruthOnPlane(const StressResult& r, const World& world, const PlaneSetup& s, size_t min_centers,
                               double rel_tol = 1e-6) {
  ASSERT_GE(r.frame.centers.size(), min_centers);
  const std::vector<Plane> surface = SurfaceTrianglePlanes(world, s);
  double worst = 0;
  for (const StripeCenter& c : r.frame.centers)
    worst = std::max(worst, TruthResidual(world.scene.sensor.camera, r.planes[0], surface, c));
  EXPECT_LE(worst, rel_tol);
}

// Every triangulated point lies within the distance a centre error of
// `bound_px` pixels can move it: bound_px * (range / fx) / sin(angle between
// the ray and the sheet), from the surface (camera frame).
inline void ExpectPointsNearSurface(const StressResult& r, const PlaneSetup& s, double bound_px) {
  const Plane surface = SurfaceInCam(s);
  for (const ScanPoint& p : r.scanned) {
    if (!p.p_in_cam) continue;
    const Eigen::Vector3d& X = *p.p_in_cam;
    double sin_angle = std::abs(r.planes[0].n.dot(X.normalized()));
    double bound = bound_px * (X.norm() / s.fx) / sin_angle;
    EXPECT_LE(std::abs(surface.SignedDistance(X)), bound) << "at (" << p.pixel.u << ", " << p.pixel.v << ")";
  }
}

// Closed-form centroid of the stripe on image row `row`: the irradiance the
// sheet casts on the surface plane (LaserProjector::IrradianceAt: intensity,
// incidence cosine and 1/r^2), sampled at the pixel centres of the row (a
// Lambertian surface's radiance is proportional to it), over the pixels above
// `floor` of the row's peak. At grazing incidence the profile is skewed (the
// far side of the beam is farther from the laser and lit more obliquely), so
// its centroid is not where the sheet's plane meets the surface.
inline std::optional<double> PredictedCentroidPx(const World& world, const PlaneSetup& s, int row,
                                                 double floor = 0.03) {
  const Camera& cam = world.scene.sensor.camera;
  const LaserProjector& laser = world.scene.sensor.lasers[0];
  const Plane surface = SurfaceInCam(s);
  std::vector<double> e(size_t(cam.width()), 0.0);
  for (int u = 0; u < cam.width(); ++u) {
    auto ray = cam.Unproject({double(u), double(row)});
    if (!ray) continue;
    auto t = surface.IntersectRay(Eigen::Vector3d::Zero(), *ray);
    if (t) e[size_t(u)] = laser.IrradianceAt(*t * *ray, surface.n);
  }
  const double peak = *std::max_element(e.begin(), e.end());
  if (!(peak > 0)) return std::nullopt;
  double sum = 0, sum_u = 0;
  for (int u = 0; u < cam.width(); ++u)
    if (e[size_t(u)] >= floor * peak) sum += e[size_t(u)], sum_u += u * e[size_t(u)];
  return sum_u / sum;
}

}  // namespace lt::test

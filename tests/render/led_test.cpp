// The LED flood light: light sampling, BSDF sampling and their combination by
// multiple importance sampling must add up to the radiance a plane reflects
// under the rectangle, L_o = integral over the LED of f(wo, wi) L cos(theta_i) dw,
// computed here by deterministic quadrature over the LED's area (400 x 400
// midpoints: L cos_i cos_l / d^2 dA, relative error ~1e-5).
#include <gtest/gtest.h>

#include "render/bsdf.h"
#include "render/frame_renderer.h"
#include "render/sampling.h"
#include "render_test_world.h"

namespace lt {
namespace {

TEST(Led, PlaneUnderTheLedMatchesQuadrature) {
  const double D = 0.05;  // plane depth; the LED sits beside the camera
  test::World world;
  world.Add(test::Rectangle({0, 0, D}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.2, 0.2));
  world.geometry->materials = {test::Plastic(0.7f, 0.6f)};
  world.Build();
  SensorRig& rig = world.scene.sensor;
  rig.camera = test::TestCamera(40, 30, 100);
  LedParams lp;
  lp.width_m = 0.02;
  lp.height_m = 0.01;
  lp.radiance = {{50.0, 50.0, 50.0}};
  lp.cam_from_led.translation() = Eigen::Vector3d(0.01, -0.005, 0);  // facing +z, toward the plane
  rig.led = Led(lp);
  ShutterParams sh;
  sh.cycle = {ShutterFrameSpec{"bright", 1e-3, false, false, true}};
  rig.shutter = ShutterSchedule(sh);
  world.scene.render.spp = 256;
  // max_bounces 1: BSDF-sampled rays from the plane can reach the LED, so both
  // strategies contribute and MIS must weigh them right.
  world.scene.render.max_bounces = 1;
  RenderedFrame frame = FrameRenderer(world.scene, *world.embree).Render(0);

  const Material& m = world.geometry->materials[0];
  Bsdf bsdf({m.base_color, m.metallic, m.roughness});
  Frame local = Frame::FromNormal(Eigen::Vector3f(0, 0, -1));
  const Camera& cam = rig.camera;
  double worst = 0;
  for (int v = 5; v < cam.height(); v += 6) {
    for (int u = 5; u < cam.width(); u += 7) {
      Eigen::Vector3d p = *cam.Unproject(Eigen::Vector2d(u, v));
      p *= D / p.z();
      Eigen::Vector3f wo = local.ToLocal((-p).normalized().cast<float>());
      double expected = 0;
      const int n = 400;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          Eigen::Vector3d q = lp.cam_from_led.translation() +
                              Eigen::Vector3d(((i + 0.5) / n - 0.5) * lp.width_m, ((j + 0.5) / n - 0.5) * lp.height_m, 0);
          Eigen::Vector3d to = q - p;
          double d2 = to.squaredNorm();
          Eigen::Vector3d wi = to / std::sqrt(d2);
          double cos_i = -wi.z(), cos_l = -wi.z();  // plane normal -z, LED normal +z
          if (cos_i <= 0) continue;
          float f = bsdf.Evaluate(wo, local.ToLocal(wi.cast<float>())).y();
          expected += f * lp.radiance[1] * cos_i * cos_l / d2 * (lp.width_m * lp.height_m / (n * n));
        }
      }
      double got = frame.radiance.At(u, v, 1);
      // 256 samples per pixel of a smooth integrand: about 1% noise per pixel.
      EXPECT_NEAR(got / expected, 1.0, 0.04) << "pixel " << u << "," << v;
      worst = std::max(worst, std::abs(got / expected - 1));
    }
  }
  std::printf("LED: largest relative deviation from quadrature %.4f\n", worst);
}

}  // namespace
}  // namespace lt

// Light paths carry the laser light that a surface reflects on from grazing
// incidence (render/path_tracer_light_paths.cpp): camera paths that leave that
// light out plus the light paths' splats give the same pixel radiance as camera
// paths that carry all of it, through a pinhole and through a thin lens; and the
// light paths' share is large enough there that a lost or doubled share would show;
// and in a moving frame, each path at its own time of the exposure.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render/path_tracer.h"
#include "render_test_world.h"

namespace lt {
namespace {

constexpr double D = 0.1;         // floor depth
constexpr double kWallY = 5e-4;   // the box's wall facing -y
constexpr int kW = 24, kH = 24;
constexpr double kFx = 2000;      // 50 um pixels at D
// The block of pixels over the foot of the wall, where the wall's reflection
// lands (within some 25 um of it): the row that ends at the wall, the columns
// about the stripe (x = 0 at D).
constexpr int kX0 = 10, kX1 = 13, kY0 = 22, kY1 = 22;

struct Estimate {
  double mean = 0, standard_error = 0;
};

Estimate MeanOf(double sum, double sum2, double n) {
  Estimate e;
  e.mean = sum / n;
  e.standard_error = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / n);
  return e;
}

struct Setup {
  test::World world;
  Camera camera;
  FrameLights lights;
  std::unique_ptr<PathTracer> tracer;
  Environment dark;

  explicit Setup(bool thin_lens) {
    // A floor at D and, beyond y = kWallY, a box 5 mm high: the laser's sheet
    // (a vertical stripe at x = 0) meets the box's wall at y = kWallY edge-on,
    // at a cosine of about kWallY / D = 0.005.
    world.Add(test::Rectangle({0, 0, D}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.05, 0.05));
    // The wall is glossy (roughness 0.1), so that it reflects most of what it receives.
    world.Add(test::Box({-0.01, kWallY, D - 0.005}, {0.01, 0.02, D}, 1));
    world.geometry->materials = {test::Plastic(0.8f, 0.5f), test::Plastic(0.8f, 0.1f)};
    world.Build();
    CameraParams p = test::TestCamera(kW, kH, kFx).params();
    p.cy = kY1 + 0.5 - kFx * kWallY / D;  // row kY1 ends at the wall's foot
    if (thin_lens) {
      p.focus_distance_m = D - 0.002;
      p.f_number = 2;
    }
    camera = Camera(p);
    world.scene.sensor.camera = camera;
    world.scene.sensor.lasers = {test::TestLaser(0.03, D, 5e-3, 2e-3)};
    lights = MakeFrameLights(world.scene.sensor, Pose::Identity(), 1.0, 0.0, 0.0);
    PathTracerOptions options;
    options.max_bounces = 2;
    tracer = std::make_unique<PathTracer>(*world.embree, dark, nullptr, options, 1);
  }

  // Mean laser radiance over the block from camera paths, n per pixel.
  Estimate CameraPaths(bool grazing_by_light_paths, int n) const {
    FrameLights l = lights;
    l.grazing_by_light_paths = grazing_by_light_paths;
    TraceStats stats;
    double sum = 0, sum2 = 0, count = 0;
    for (int y = kY0; y <= kY1; ++y)
      for (int x = kX0; x <= kX1; ++x)
        for (int i = 0; i < n; ++i) {
          Rng rng = Rng::For(5, 0, uint64_t(y * kW + x), uint64_t(i));
          const Eigen::Vector2d u(x - 0.5 + rng.NextDouble(), y - 0.5 + rng.NextDouble());
          const Eigen::Vector2d lens(rng.NextDouble(), rng.NextDouble());
          const auto ray = camera.GenerateRay(u, lens);
          Eigen::Vector3f rgb = Eigen::Vector3f::Zero();
          std::array<float, 1> mono{0.0f};
          if (ray) tracer->Trace(Ray{ray->origin, ray->direction, 0, INFINITY}, l, rng, &rgb, mono, &stats);
          sum += mono[0];
          sum2 += double(mono[0]) * mono[0];
          ++count;
        }
    return MeanOf(sum, sum2, count);
  }

  // Mean over the block of the light paths' radiance, over `runs` seeds.
  Estimate LightPaths(int64_t paths, int runs) const {
    FrameLights l = lights;
    l.grazing_by_light_paths = true;
    double sum = 0, sum2 = 0;
    for (int r = 0; r < runs; ++r) {
      Image<float> splat(kW, kH, 1, 0.0f);
      TraceStats stats;
      tracer->TraceLightPaths(l, camera, Pose::Identity(), paths, uint64_t(100 + r), 0, &splat, &stats);
      double block = 0;
      for (int y = kY0; y <= kY1; ++y)
        for (int x = kX0; x <= kX1; ++x) block += splat.At(x, y);
      block /= (kX1 - kX0 + 1) * (kY1 - kY0 + 1);
      sum += block;
      sum2 += block * block;
    }
    return MeanOf(sum, sum2, runs);
  }
};

void ExpectSameRadiance(bool thin_lens) {
  const Setup s(thin_lens);
  const int n_all = 48000, n_rest = 8000;
  const Estimate all = s.CameraPaths(false, n_all);
  const Estimate rest = s.CameraPaths(true, n_rest);
  const Estimate glint = s.LightPaths(100000, 8);
  std::printf("block radiance: camera paths %.6g +- %.2g; without grazing %.6g +- %.2g + light paths %.6g +- %.2g\n",
              all.mean, all.standard_error, rest.mean, rest.standard_error, glint.mean, glint.standard_error);
  const double error = std::sqrt(all.standard_error * all.standard_error + rest.standard_error * rest.standard_error +
                                 glint.standard_error * glint.standard_error);
  // Same expectation, within 4 combined standard errors (the seeds are fixed,
  // so it is decided once).
  EXPECT_NEAR(all.mean, rest.mean + glint.mean, 4 * error);
  // The light paths' share is larger than that tolerance: leaving it out, or
  // counting it twice, fails the comparison above.
  EXPECT_GT(glint.mean, 5 * error);
  // What the light paths are for: camera paths carry those reflections only by
  // rare bright samples. Without them, one camera sample's standard deviation
  // is at least four times smaller.
  EXPECT_LT(rest.standard_error * std::sqrt(double(n_rest)), 0.25 * all.standard_error * std::sqrt(double(n_all)));
}

TEST(LightPaths, GrazingReflectionsThroughAPinholeKeepThePixelsRadiance) { ExpectSameRadiance(false); }

// A scanner moving during the exposure: each light path takes its own time, the
// laser and the camera posed then. The camera slides 150 um toward the wall
// (the wall's foot crosses 3 rows) and 0.3 mm away from the floor (the stripe,
// from a projector 30 mm beside the camera, crosses 1.8 columns) over the
// exposure; the frame's splats must be the mean over the exposure of still
// frames' splats, here 64 poses at the middles of equal parts of it.
TEST(LightPaths, AMovingScannersPathsSplatTheMeanOverTheExposure) {
  const lt::Setup s(false);
  constexpr double kT = 1e-3;
  constexpr int kPoses = 64, kRuns = 8;
  constexpr int64_t kPaths = 64000;
  auto world_from_cam_at = [](double t) {
    Pose p = Pose::Identity();
    p.translation() = Eigen::Vector3d(0, 150e-6 * t / kT, -0.3e-3 * t / kT);
    return p;
  };
  // From the middle to either end the camera moves 84 um: 16 slices of
  // grazing cells (5 um at the floor).
  const ExposureMotion motion{0.0, kT, world_from_cam_at, 0.5 * std::hypot(150e-6, 0.3e-3)};
  // Per row, mean and standard error over the runs of the splats' sum over the row.
  struct Rows {
    std::vector<double> sum = std::vector<double>(kH, 0.0), sum2 = std::vector<double>(kH, 0.0);
    void Add(const Image<float>& splat) {
      for (int y = 0; y < kH; ++y) {
        double row = 0;
        for (int x = 0; x < kW; ++x) row += splat.At(x, y);
        sum[size_t(y)] += row, sum2[size_t(y)] += row * row;
      }
    }
    Estimate Row(int y) const { return MeanOf(sum[size_t(y)], sum2[size_t(y)], kRuns); }
  } moving, still, mid_only;
  const Pose mid = world_from_cam_at(0.5 * kT);
  for (int r = 0; r < kRuns; ++r) {
    Image<float> splat(kW, kH, 1, 0.0f), mean(kW, kH, 1, 0.0f);
    TraceStats stats;
    FrameLights l = MakeFrameLights(s.world.scene.sensor, mid, 1.0, 0.0, 0.0);
    l.grazing_by_light_paths = true;
    s.tracer->TraceLightPaths(l, s.camera, mid, kPaths, uint64_t(200 + r), 0, &splat, &stats, &motion);
    moving.Add(splat);
    Image<float> at_mid(kW, kH, 1, 0.0f);  // what a frame that ignored the motion would splat
    s.tracer->TraceLightPaths(l, s.camera, mid, kPaths, uint64_t(200 + r), 0, &at_mid, &stats);
    mid_only.Add(at_mid);
    for (int i = 0; i < kPoses; ++i) {
      const Pose at = world_from_cam_at((i + 0.5) / kPoses * kT);
      FrameLights li = MakeFrameLights(s.world.scene.sensor, at, 1.0, 0.0, 0.0);
      li.grazing_by_light_paths = true;
      Image<float> one(kW, kH, 1, 0.0f);
      s.tracer->TraceLightPaths(li, s.camera, at, kPaths / kPoses, uint64_t(1000 * r + i), 0, &one, &stats);
      for (size_t k = 0; k < one.pixels.size(); ++k) mean.pixels[k] += one.pixels[k] / kPoses;
    }
    still.Add(mean);
  }
  double total = 0, largest = 0;
  for (int y = 0; y < kH; ++y) total += still.Row(y).mean, largest = std::max(largest, still.Row(y).mean);
  int rows_off = 0;  // rows where the mid pose's splats alone fail the comparison
  for (int y = 0; y < kH; ++y) {
    const Estimate m = moving.Row(y), q = still.Row(y), c = mid_only.Row(y);
    std::printf("row %d: moving %.5g +- %.2g, mean of still poses %.5g +- %.2g, mid pose only %.5g\n", y, m.mean,
                m.standard_error, q.mean, q.standard_error, c.mean);
    // 4 combined standard errors, and 2% of the largest row for the 64 poses'
    // midpoint rule in time.
    EXPECT_NEAR(m.mean, q.mean, 4 * std::hypot(m.standard_error, q.standard_error) + 0.02 * largest) << "row " << y;
    rows_off += std::abs(c.mean - q.mean) > 4 * std::hypot(c.standard_error, q.standard_error) + 0.02 * largest;
  }
  // The comparison tells the motion: the splats of the mid pose alone fail it.
  EXPECT_GE(rows_off, 2);
  EXPECT_GT(total, 0);
}

TEST(LightPaths, GrazingReflectionsThroughAThinLensKeepThePixelsRadiance) { ExpectSameRadiance(true); }

}  // namespace
}  // namespace lt

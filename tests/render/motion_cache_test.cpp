// The subsurface cache of a scanner that moves during the exposure
// (FrameRenderer::Render, CacheSlices): beyond the bound of one cache (no
// surface moving by more than a quarter of the entry spacing from the middle of
// the exposure to its ends) the exposure is cut into time slices, each with the
// caches cast at the pose of its middle, and a camera sample takes the slice
// holding its time.
//
// The scene: a flat subsurface slab under a scanner that slides across its
// stripe. The slab is flat and much wider than the view, and the lasers move
// with the camera, so the moving frame's expected image is the still frame's:
// the sliced caches must give the still frame's stripe and glow, the same light
// as Monte Carlo in the same moving frame, and far less noise than it.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "render/frame_renderer.h"
#include "render_test_world.h"

namespace lt {
namespace {

constexpr double D = 0.1, kMfp = 0.5e-3, kFx = 1000, kExposure = 1e-4;

struct Profile {
  std::vector<double> columns;  // laser radiance of each column, mean of rows 10-29
  std::vector<double> glow;     // the pixels of rows 10-29 0.5 to 3 mm beside the stripe
  int slices = -1;              // FrameStats::entry_tree_slices
};

// The slab seen by a 160x40 camera (0.1 mm pixels), one sheet along the image's
// columns at its centre, 16 samples in every near pixel; the scanner slides
// along x (across the stripe) at speed_m_s (0: still).
Profile Render(double speed_m_s, bool cache, uint64_t seed) {
  test::World world;
  world.Add(test::Rectangle({0, 0, D}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.2, 0.2));
  Material pla = test::Plastic(0.8f, 0.5f);
  pla.subsurface = Subsurface{Eigen::Vector3d::Constant(kMfp), kMfp};
  world.geometry->materials = {pla};
  world.Build();
  SensorRig& rig = world.scene.sensor;
  rig.camera = test::TestCamera(160, 40, kFx);
  rig.lasers = {test::TestLaser(0.03, D, 5e-3, 2e-3)};
  ShutterParams sh;
  sh.cycle = {ShutterFrameSpec{"dim", kExposure, true, false, false}};
  rig.shutter = ShutterSchedule(sh);
  world.scene.render.spp = 16;
  world.scene.render.adaptive_noise = 0;  // every near pixel takes all 16
  world.scene.render.max_bounces = 0;
  world.scene.render.subsurface_cache = cache;
  const auto dir = std::filesystem::temp_directory_path() / ("lt_motion_cache_" + std::to_string(::getpid()));
  if (speed_m_s > 0) world.scene.motion = test::SlidingAlongX(dir, speed_m_s);
  RenderOverrides o;
  o.seed = seed;
  const RenderedFrame f = FrameRenderer(world.scene, *world.embree, o).Render(0);
  std::filesystem::remove_all(dir);
  Profile p;
  p.slices = f.stats.entry_tree_slices;
  const Camera& cam = rig.camera;
  for (int u = 0; u < cam.width(); ++u) {
    double sum = 0;
    const double x_mm = std::abs(u - cam.cx()) * D / kFx * 1e3;
    for (int v = 10; v < 30; ++v) {
      sum += f.radiance.At(u, v, 3);
      if (x_mm > 0.5 && x_mm < 3) p.glow.push_back(f.radiance.At(u, v, 3));
    }
    p.columns.push_back(sum / 20);
  }
  return p;
}

double Total(const std::vector<double>& a) {
  double s = 0;
  for (double x : a) s += x;
  return s;
}

// RMS of the difference of two seeds' pixels over their mean: the noise (x sqrt 2).
double Noise(const std::vector<double>& a, const std::vector<double>& b) {
  double d2 = 0;
  for (size_t i = 0; i < a.size(); ++i) d2 += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(d2 / double(a.size())) / ((Total(a) + Total(b)) / (2.0 * double(a.size())));
}

TEST(SubsurfaceTimeSlices, MovingFrameGivesTheStillStripeWithLessNoiseThanMonteCarlo) {
  // The bound of one cache: a quarter of the entry spacing, mfp / 32 = 15.6 um
  // from the middle of the exposure to either end. 1 m/s over 100 us moves the
  // scanner 50 um either way: four slices of 12.5 um. 2 m/s: seven of 14.3 um.
  const Profile still = Render(0.0, true, 1);
  const Profile sliced_a = Render(1.0, true, 1), sliced_b = Render(1.0, true, 2);
  const Profile mc_a = Render(1.0, false, 1), mc_b = Render(1.0, false, 2);
  const Profile faster = Render(2.0, true, 1);
  EXPECT_EQ(still.slices, 1);
  EXPECT_EQ(sliced_a.slices, 4);
  EXPECT_EQ(faster.slices, 7);
  EXPECT_EQ(mc_a.slices, 0);
  const double n_sliced = Noise(sliced_a.glow, sliced_b.glow), n_mc = Noise(mc_a.glow, mc_b.glow);
  double peak = 0, worst = 0, worst_faster = 0;
  for (double c : still.columns) peak = std::max(peak, c);
  for (size_t u = 0; u < still.columns.size(); ++u) {
    worst = std::max(worst, std::abs(sliced_a.columns[u] - still.columns[u]) / peak);
    worst_faster = std::max(worst_faster, std::abs(faster.columns[u] - still.columns[u]) / peak);
  }
  std::printf(
      "moving slab: glow noise sliced %.5f, Monte Carlo %.5f; largest column difference from the still frame "
      "%.4f (4 slices), %.4f (7 slices) of the peak; total sliced / still %.4f, sliced / Monte Carlo %.4f\n",
      n_sliced, n_mc, worst, worst_faster, Total(sliced_a.columns) / Total(still.columns),
      Total(sliced_a.columns) / Total(mc_a.columns));
  // The still frame's stripe and glow, column by column: a sample sees the lit
  // line up to 12.5 um (a quarter of the stripe's sigma) off its slice's cache,
  // an error that cancels over the slice's times (stratified, 16 a pixel) to
  // first order; 0.5% of the peak (measured 0.09% and 0.13%; the middle
  // slice's caches for every time: 3.0% and 5.1%).
  EXPECT_LT(worst, 0.005);
  EXPECT_LT(worst_faster, 0.005);
  EXPECT_NEAR(Total(sliced_a.columns) / Total(still.columns), 1.0, 0.005);
  // The same light as Monte Carlo in the moving frame (whose noise over the
  // 160 columns is under 1%), and at most a fifth of its noise.
  EXPECT_NEAR(Total(sliced_a.columns) / Total(mc_a.columns), 1.0, 0.02);
  EXPECT_LT(n_sliced, 0.2 * n_mc);
}

TEST(SubsurfaceTimeSlices, BeyondSixteenSlicesTheFrameUsesMonteCarlo) {
  // 10 m/s: 500 um either way, 32 slices of the bound: Monte Carlo, as before.
  EXPECT_EQ(Render(10.0, true, 1).slices, 0);
  // 0.2 m/s: 10 um either way, within one cache's bound.
  EXPECT_EQ(Render(0.2, true, 1).slices, 1);
}

}  // namespace
}  // namespace lt

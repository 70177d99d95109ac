// Stripe extraction speed: each method at 640x480, 2688x480 and 2688x1620 on
// a single-stripe 8-bit frame, with 1 and 2 threads. The frame is synthetic
// (pipeline/synthetic_stripes.h): a slightly tilted and curved Gaussian stripe
// (sigma 2 px, FWHM 4.7 px, peak 200 DN) on an 8 DN background with 2 DN
// Gaussian noise, rounded to 8 bits. Run with --benchmark_repetitions=N and
// read the medians (docs/performance.md).
//
// BM_ExtractRendered: the same at 640x480 on a rendered frame (the demo's slot
// test part lit by one vertical laser sheet, 10-bit DN, 4 samples per pixel),
// rendered once when the benchmark starts (a few seconds). Larger rendered
// frames would take minutes to render, so the larger sizes use the synthetic frame.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "pipeline/stripe_extractor.h"
#include "pipeline/synthetic_stripes.h"
#include "render/frame_renderer.h"
#include "scene/embree_scene.h"
#include "scene/scene_file.h"
#include "scene/scene_geometry.h"

namespace {

const lt::Image<uint8_t>& Frame(int width, int height) {
  static std::map<std::pair<int, int>, std::unique_ptr<lt::Image<uint8_t>>> cache;
  auto& slot = cache[{width, height}];
  if (!slot) {
    lt::SyntheticFrame f;
    f.width = width;
    f.height = height;
    f.background = 8;
    f.noise_sigma = 2;
    f.seed = 7;
    lt::SyntheticStripe s;
    s.shape = lt::SyntheticStripe::Shape::kArc;  // a gentle curve, ~5 degrees of tilt over the frame
    s.radius = 20.0 * height;
    s.cu = 0.45 * width - s.radius;
    s.cv = 0.3 * height;
    s.sigma = 2;
    s.amplitude = 200;
    f.stripes.push_back(s);
    slot = std::make_unique<lt::Image<uint8_t>>(lt::QuantizeImage<uint8_t>(lt::RenderSyntheticFrame(f)));
  }
  return *slot;
}

// Method 4: steger with the expected width measured on the frame (the default).
void BM_Extract(benchmark::State& state) {
  const bool measured_width = state.range(0) == 4;
  const auto method = measured_width ? lt::ExtractionMethod::kSteger : lt::ExtractionMethod(state.range(0));
  const int width = int(state.range(1)), height = int(state.range(2)), threads = int(state.range(3));
  const lt::Image<uint8_t>& img = Frame(width, height);
  lt::ExtractionOptions o;
  o.method = method;
  o.threshold = 60;
  o.expected_width = measured_width ? lt::ExtractionOptions::kAuto : 4.7;
  o.threads = threads;
  lt::StripeExtractor extractor(o);
  std::vector<lt::StripePoint> points;
  extractor.Extract(img.View(), &points);  // buffers grow once
  for (auto _ : state) {
    extractor.Extract(img.View(), &points);
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["points"] = double(points.size());
  state.SetLabel(std::string(lt::MethodName(method)) + (measured_width ? " (width measured) " : " ") +
                 std::to_string(width) + "x" + std::to_string(height) + " threads " + std::to_string(threads));
}

void Register(benchmark::internal::Benchmark* b) {
  for (int m = 0; m < 5; ++m)
    for (auto [w, h] : {std::pair{640, 480}, std::pair{2688, 480}, std::pair{2688, 1620}})
      for (int t : {1, 2}) b->Args({m, w, h, t});
  b->ArgNames({"method", "w", "h", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_Extract)->Apply(Register);

// A 640x480 laser frame of tests/data/scenes/scan_distorted.json with the camera
// at 4x the resolution (4.8 um pixels, same field of view) and the projector
// turned so that its sheet makes a vertical stripe (searched along rows, like
// the synthetic frame); no environment light.
const lt::Image<uint16_t>& RenderedFrame() {
  static std::unique_ptr<lt::Image<uint16_t>> frame;
  if (!frame) {
    lt::SceneFile scene = lt::LoadSceneFile(std::string(LT_SOURCE_DIR) + "/tests/data/scenes/scan_distorted.json");
    lt::CameraParams cp = scene.sensor.camera.params();
    cp.width = 640;
    cp.height = 480;
    cp.pixel_pitch_m /= 4;
    cp.fx *= 4;
    cp.fy *= 4;
    cp.cx = 319.5;
    cp.cy = 239.5;
    scene.sensor.camera = lt::Camera(cp);
    lt::LaserParams lp = scene.sensor.lasers.at(0).params();
    lp.cam_from_projector = lt::Pose::Identity();
    lp.cam_from_projector.translation() = Eigen::Vector3d(0.04, 0, 0);
    lp.cam_from_projector.linear() = (Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(-26.565 * M_PI / 180, Eigen::Vector3d::UnitX()))
                                         .toRotationMatrix();
    lp.power_w *= 16;  // pixels of a quarter the pitch gather 1/16 of the light
    scene.sensor.lasers.at(0) = lt::LaserProjector(lp);
    scene.environment = lt::Environment{};
    auto geometry = std::make_shared<lt::SceneGeometry>(lt::LoadSceneGeometry(scene));
    lt::EmbreeScene embree(geometry);
    lt::RenderOverrides overrides;
    overrides.spp = 4;
    lt::FrameRenderer renderer(scene, embree, overrides);
    frame = std::make_unique<lt::Image<uint16_t>>(renderer.Render(0).raw);  // frame 0 is the laser frame
  }
  return *frame;
}

void BM_ExtractRendered(benchmark::State& state) {
  const auto method = lt::ExtractionMethod(state.range(0));
  const int threads = int(state.range(1));
  const lt::Image<uint16_t>& img = RenderedFrame();
  lt::ExtractionOptions o;
  o.method = method;
  o.threshold = 102.3;  // 10% of the 10-bit full scale
  o.expected_width = 4;
  o.threads = threads;
  lt::StripeExtractor extractor(o);
  std::vector<lt::StripePoint> points;
  extractor.Extract(img.View(), &points);
  for (auto _ : state) {
    extractor.Extract(img.View(), &points);
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["points"] = double(points.size());
  state.SetLabel(std::string(lt::MethodName(method)) + " rendered 640x480 threads " + std::to_string(threads));
}

BENCHMARK(BM_ExtractRendered)
    ->ArgsProduct({{0, 1, 2, 3}, {1, 2}})
    ->ArgNames({"method", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

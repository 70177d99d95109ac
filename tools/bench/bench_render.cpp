// Renderer benchmarks on the demo scene (scenes/demo/scene.json):
//  - DimFrame640/spp/noise: a 640x480 dim (laser) frame at several sample
//    counts, with the adaptive stop at several fractions of the sensor noise
//    (render.adaptive_noise in hundredths) and without it (0), with the error of a
//    centre-of-mass extraction on its laser radiance against a 256-spp
//    reference (counters com_*_px; wide_rms_px with a 24 px window) and its
//    noise against a second render with another seed (noise_rms_px; the share
//    of its variance in the noisiest 4% of the columns, noise_top4_share), and
//    the camera samples' pass and the other passes' time (samples_ms,
//    other_passes_ms, the last iteration's): run time against error;
//  - DimFrame640Noise/bounces: the noise of one 16-spp render of that frame, per
//    max_bounces (three pairs of seeds, pooled);
//  - DimFrame640Once/spp: that frame alone, one render, for profilers;
//  - BrightFrame1280: the 1280x1024 bright frame (LED, 2 bounces, 16 spp);
//  - EmbreePrimaryRays: a bare rtcIntersect1 loop over the 1280x1024 pinhole
//    rays of the demo camera, the upper bound on rays per second; the renderer's
//    own rays per second over it is its efficiency ratio.
// Threads: all (2 here) unless LT_BENCH_THREADS is set.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

#include "core/heap_reuse.h"
#include "pipeline/stripe_extractor.h"
#include "pipeline/window_centroid.h"
#include "render/frame_renderer.h"
#include "scene/embree_scene.h"
#include "scene/scene_file.h"
#include "resized_camera.h"

namespace lt {
namespace {

int BenchThreads() {
  const char* t = std::getenv("LT_BENCH_THREADS");
  return t ? std::atoi(t) : 0;
}

struct Demo {
  SceneFile scene;
  std::shared_ptr<SceneGeometry> geometry;
  std::unique_ptr<EmbreeScene> embree;

  explicit Demo(int width, int height) {
    scene = LoadSceneFile(std::string(LT_SOURCE_DIR) + "/scenes/demo/scene.json");
    scene.sensor.camera = ResizedCamera(scene.sensor.camera, width, height);  // same field of view, larger pixels
    geometry = std::make_shared<SceneGeometry>(LoadSceneGeometry(scene));
    embree = std::make_unique<EmbreeScene>(geometry);
  }
};

Demo& Demo640() {
  static Demo d(640, 480);
  return d;
}

Image<float> LaserImage(const Image<float>& radiance) {
  Image<float> laser(radiance.width, radiance.height, 1);
  for (int y = 0; y < radiance.height; ++y)
    for (int x = 0; x < radiance.width; ++x) laser.At(x, y) = radiance.At(x, y, 3);
  return laser;
}

// Median over the columns of each column's brightest laser radiance: the
// stripe's typical peak, which a few bright pixels at slot edges do not move.
double TypicalPeak(const Image<float>& laser) {
  std::vector<float> peaks;
  for (int x = 0; x < laser.width; ++x) {
    float m = 0;
    for (int y = 0; y < laser.height; ++y) m = std::max(m, laser.At(x, y));
    if (m > 0) peaks.push_back(m);
  }
  if (peaks.empty()) return 0;
  std::nth_element(peaks.begin(), peaks.begin() + peaks.size() / 2, peaks.end());
  return peaks[peaks.size() / 2];
}

// Centre of mass per column (the pipeline's com: a window of 1.25 FWHM either
// side, centred on the centroid itself, docs/extraction.md) with weights above a
// fixed threshold, 10% of the reference's typical peak. `window` > 0 fixes the
// half window instead.
std::vector<StripePoint> Com(const Image<float>& laser, double threshold, int window = 0) {
  ExtractionOptions o;
  o.method = ExtractionMethod::kCom;
  o.axis = SearchAxis::kCols;  // the demo's stripe runs along the rows
  o.threshold = threshold;
  o.background = threshold;
  o.window = window;
  o.threads = 1;
  return StripeExtractor(o).Extract(laser.View());
}

// Column-wise |v - v_ref| of the columns both extractions found.
std::vector<double> ComErrors(const std::vector<StripePoint>& a, const std::vector<StripePoint>& ref) {
  std::map<int, double> r;
  for (const auto& p : ref) r[int(std::lround(p.u))] = p.v;
  std::vector<double> e;
  for (const auto& p : a) {
    auto it = r.find(int(std::lround(p.u)));
    if (it != r.end()) e.push_back(std::abs(p.v - it->second));
  }
  std::sort(e.begin(), e.end());
  return e;
}

// Where the pipeline's com window around a reference centre stops: the valleys
// to neighbouring peaks in the reference's column (ValleyBounds from the
// column's maximum within the window; +-HUGE_VAL where none).
struct WindowBounds {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
};
std::vector<WindowBounds> ReferenceBounds(const Image<float>& laser, double threshold, const std::vector<StripePoint>& ref) {
  std::vector<WindowBounds> bounds(ref.size());
  std::vector<float> column(size_t(laser.height));
  for (size_t i = 0; i < ref.size(); ++i) {
    const int x = int(std::lround(ref[i].u));
    for (int y = 0; y < laser.height; ++y) column[size_t(y)] = laser.At(x, y);
    const double h = ComHalfWindow(ref[i].width, 1, 0);
    const int a = std::max(0, int(std::floor(ref[i].v - h))), b = std::min(laser.height - 1, int(std::ceil(ref[i].v + h)));
    int peak = a;
    for (int y = a + 1; y <= b; ++y)
      if (column[size_t(y)] > column[size_t(peak)]) peak = y;
    ValleyBounds(column.data(), laser.height, peak, peak, double(column[size_t(peak)]), threshold, int(std::ceil(h)) + 1,
                 &bounds[i].lo, &bounds[i].hi);
  }
  return bounds;
}

// The pipeline's com in every column where the reference has a centre, with the
// reference's window (its FWHM, stopped at the reference's valleys to
// neighbouring peaks) started at the reference's centre rather than at the
// column's own maximum: where a column holds two stripes of nearly equal height
// (the part's top and a slot floor, 5 px apart), the maximum picks one or the
// other by the noise of a few pixels, a choice that is the extractor's, not
// the render's. Returns v per reference point (NaN where none).
std::vector<double> ComAtReference(const Image<float>& laser, double threshold, const std::vector<StripePoint>& ref,
                                   const std::vector<WindowBounds>& bounds) {
  std::vector<double> v(ref.size(), std::nan(""));
  std::vector<float> column(size_t(laser.height));
  for (size_t i = 0; i < ref.size(); ++i) {
    const int x = int(std::lround(ref[i].u));
    for (int y = 0; y < laser.height; ++y) column[size_t(y)] = laser.At(x, y);
    SelfCentredCentroid(column.data(), laser.height, ref[i].v, ComHalfWindow(ref[i].width, 1, 0), threshold, &v[i],
                        bounds[i].lo, bounds[i].hi);
  }
  return v;
}

// Sorted |a - b| over the entries both have.
std::vector<double> Differences(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> e;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i)
    if (std::isfinite(a[i]) && std::isfinite(b[i])) e.push_back(std::abs(a[i] - b[i]));
  std::sort(e.begin(), e.end());
  return e;
}

double Rms(const std::vector<double>& e) {
  double s = 0;
  for (double x : e) s += x * x;
  return e.empty() ? -1 : std::sqrt(s / double(e.size()));
}

// The earlier, wide measure: a window of 24 px either side of the column's
// maximum, which takes in the stripe's dim glow and a second stripe in the
// column (docs/performance.md).
constexpr int kWideWindow = 24;

struct ReferenceStripe {
  double threshold = 0;
  std::vector<StripePoint> centers;  // the pipeline's com
  std::vector<WindowBounds> bounds;  // where its windows stop
  std::vector<double> v;             // their v
  std::vector<StripePoint> wide;     // com over kWideWindow
};

// The noise of one render from two with different seeds: the RMS of their
// centres' difference (ComAtReference) over sqrt(2); `columns`: how many
// columns both have; `differences`: the sorted |v_a - v_b| behind it.
double NoiseRms(const Image<float>& a, const Image<float>& b, const ReferenceStripe& ref, size_t* columns = nullptr,
                std::vector<double>* differences = nullptr) {
  const std::vector<double> e =
      Differences(ComAtReference(a, ref.threshold, ref.centers, ref.bounds),
                  ComAtReference(b, ref.threshold, ref.centers, ref.bounds));
  if (columns) *columns = e.size();
  if (differences) *differences = e;
  return Rms(e) / std::sqrt(2.0);
}

// The share of the squared differences (sorted ascending) held by the largest
// 4% of them: about 0.04 for noise spread evenly over the columns, near 1 when a
// few columns' heavy-tailed pixels make the RMS (docs/performance.md).
double TopShare(const std::vector<double>& sorted) {
  if (sorted.empty()) return -1;
  const size_t top = std::max<size_t>(1, (sorted.size() * 4 + 99) / 100);
  double all = 0, largest = 0;
  for (size_t i = 0; i < sorted.size(); ++i) {
    all += sorted[i] * sorted[i];
    if (i + top >= sorted.size()) largest += sorted[i] * sorted[i];
  }
  return all > 0 ? largest / all : 0;
}

// 256 samples in every pixel (no adaptive stop), another seed.
const ReferenceStripe& Reference() {
  static ReferenceStripe ref = [] {
    Demo& d = Demo640();
    SceneFile scene = d.scene;
    scene.render.adaptive_noise = 0;
    RenderOverrides o;
    o.spp = 256;
    o.seed = 999;
    o.threads = BenchThreads();
    Image<float> laser = LaserImage(FrameRenderer(scene, *d.embree, o).Render(1).radiance);
    ReferenceStripe r;
    r.threshold = 0.1 * TypicalPeak(laser);
    r.centers = Com(laser, r.threshold);
    r.bounds = ReferenceBounds(laser, r.threshold, r.centers);
    for (const auto& p : r.centers) r.v.push_back(p.v);
    r.wide = Com(laser, r.threshold, kWideWindow);
    return r;
  }();
  return ref;
}

void BM_DimFrame640(benchmark::State& state) {
  Demo& d = Demo640();
  const auto& ref = Reference();
  SceneFile scene = d.scene;
  // range(1): the adaptive stop's fraction of the sensor noise in hundredths
  // (render.adaptive_noise; 0: every near pixel takes spp samples).
  scene.render.adaptive_noise = double(state.range(1)) / 100.0;
  RenderOverrides o;
  o.spp = int(state.range(0));
  o.threads = BenchThreads();
  FrameRenderer renderer(scene, *d.embree, o);
  RenderedFrame frame;
  for (auto _ : state) frame = renderer.Render(1);
  const Image<float> laser = LaserImage(frame.radiance);
  const std::vector<double> v = ComAtReference(laser, ref.threshold, ref.centers, ref.bounds);
  const std::vector<double> e = Differences(v, ref.v);
  // The frame's own noise, free of the reference's: a second render with
  // another seed (outside the timing), |v - v2| / sqrt(2).
  o.seed = 7;
  const Image<float> laser2 = LaserImage(FrameRenderer(scene, *d.embree, o).Render(1).radiance);
  std::vector<double> noise_differences;
  state.counters["noise_rms_px"] = NoiseRms(laser, laser2, ref, nullptr, &noise_differences);
  state.counters["noise_top4_share"] = TopShare(noise_differences);
  state.counters["wide_rms_px"] = Rms(ComErrors(Com(laser, ref.threshold, kWideWindow), ref.wide));
  state.counters["com_rms_px"] = Rms(e);
  state.counters["com_median_px"] = e.empty() ? -1 : e[e.size() / 2];
  state.counters["com_p90_px"] = e.empty() ? -1 : e[e.size() * 9 / 10];
  state.counters["columns"] = double(e.size());
  state.counters["rays_per_s"] = benchmark::Counter(double(frame.stats.rays), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["near_pixels"] = double(frame.stats.near_pixels);
  state.counters["gt_ms"] = frame.stats.ground_truth_ms;
  state.counters["samples"] = double(frame.stats.samples);
  // The last iteration's passes (manifest stats.pass_ms): the camera samples
  // against the rest.
  state.counters["samples_ms"] = frame.stats.pass_ms.samples;
  state.counters["other_passes_ms"] = frame.stats.pass_ms.Sum() - frame.stats.pass_ms.samples;
}
// Arguments: samples per pixel, and render.adaptive_noise in hundredths (25:
// the default; 0: no adaptive stop).
BENCHMARK(BM_DimFrame640)
    ->Args({1, 25})
    ->Args({4, 25})
    ->Args({6, 25})
    ->Args({8, 25})
    ->Args({16, 25})
    ->Args({64, 25})
    ->Args({128, 25})
    ->Args({16, 0})
    ->Args({64, 0})->Unit(benchmark::kMillisecond)->UseRealTime();

// The same frame rendered once per iteration without the reference or the
// noise render, for profilers (valgrind --tool=callgrind ... --benchmark_filter=
// DimFrame640Once/1, docs/performance.md); counters as BM_DimFrame640's.
void BM_DimFrame640Once(benchmark::State& state) {
  Demo& d = Demo640();
  RenderOverrides o;
  o.spp = int(state.range(0));
  o.threads = BenchThreads();
  FrameRenderer renderer(d.scene, *d.embree, o);
  RenderedFrame frame;
  for (auto _ : state) frame = renderer.Render(1);
  state.counters["samples"] = double(frame.stats.samples);
  state.counters["samples_ms"] = frame.stats.pass_ms.samples;
  state.counters["other_passes_ms"] = frame.stats.pass_ms.Sum() - frame.stats.pass_ms.samples;
}
BENCHMARK(BM_DimFrame640Once)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// Where the dim frame's noise comes from: renders with different seeds at 16 spp
// (every near pixel at spp), per max_bounces, in kNoisePairs pairs. One pair's
// figure is uncertain by a factor of two (the slot-edge columns are heavy-tailed:
// 0.041, 0.019 and 0.016 px for three pairs with no bounce), so com_rms_px pools
// the pairs: the RMS of all centre differences over sqrt(2), the noise of one
// render; com_pair_min_px and com_pair_max_px are the pairs' extremes.
constexpr int kNoisePairs = 3;
void BM_DimFrame640Noise(benchmark::State& state) {
  Demo& d = Demo640();
  const ReferenceStripe& ref = Reference();
  SceneFile scene = d.scene;
  scene.render.adaptive_noise = 0;
  scene.render.max_bounces = int(state.range(0));
  RenderOverrides o;
  o.spp = 16;
  o.threads = BenchThreads();
  std::vector<Image<float>> images(2 * kNoisePairs);
  for (auto _ : state) {
    for (size_t i = 0; i < images.size(); ++i) {
      o.seed = 11 + uint64_t(i);
      images[i] = LaserImage(FrameRenderer(scene, *d.embree, o).Render(1).radiance);
    }
  }
  double sum2 = 0, wide2 = 0, lo = INFINITY, hi = 0;
  size_t columns = 0, wide_columns = 0;
  for (int k = 0; k < kNoisePairs; ++k) {
    const Image<float>& a = images[size_t(2 * k)];
    const Image<float>& b = images[size_t(2 * k + 1)];
    size_t n = 0;
    const double pair = NoiseRms(a, b, ref, &n);
    sum2 += pair * pair * double(n);
    columns += n;
    lo = std::min(lo, pair), hi = std::max(hi, pair);
    const std::vector<double> wide = ComErrors(Com(a, ref.threshold, kWideWindow), Com(b, ref.threshold, kWideWindow));
    for (double e : wide) wide2 += e * e;
    wide_columns += wide.size();
  }
  state.counters["com_rms_px"] = columns ? std::sqrt(sum2 / double(columns)) : -1;
  state.counters["com_pair_min_px"] = lo;
  state.counters["com_pair_max_px"] = hi;
  state.counters["wide_rms_px"] = wide_columns ? std::sqrt(wide2 / double(wide_columns) / 2.0) : -1;
  state.counters["columns"] = double(columns) / kNoisePairs;
}
BENCHMARK(BM_DimFrame640Noise)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_BrightFrame1280(benchmark::State& state) {
  static Demo d(1280, 1024);
  RenderOverrides o;
  o.spp = 16;
  o.threads = BenchThreads();
  FrameRenderer renderer(d.scene, *d.embree, o);
  RenderedFrame frame;
  for (auto _ : state) frame = renderer.Render(0);
  state.counters["rays_per_s"] = benchmark::Counter(double(frame.stats.rays), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BrightFrame1280)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_EmbreePrimaryRays(benchmark::State& state) {
  static Demo d(1280, 1024);
  const Camera& cam = d.scene.sensor.camera;
  const Pose world_from_cam = WorldFromCamAt(d.scene.motion, 0);
  std::vector<RTCRay> rays;
  for (int y = 0; y < cam.height(); ++y) {
    for (int x = 0; x < cam.width(); ++x) {
      Eigen::Vector3d dir = world_from_cam.linear() * *cam.Unproject(Eigen::Vector2d(x, y));
      Eigen::Vector3d org = d.embree->RenderFromWorld(world_from_cam.translation());
      RTCRay r{};
      r.org_x = float(org.x()), r.org_y = float(org.y()), r.org_z = float(org.z());
      r.dir_x = float(dir.x()), r.dir_y = float(dir.y()), r.dir_z = float(dir.z());
      r.tnear = 0, r.tfar = 1e30f, r.mask = ~0u, r.flags = 0;
      rays.push_back(r);
    }
  }
  size_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (const RTCRay& r : rays) {
      RTCRayHit rh;
      rh.ray = r;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(d.embree->handle(), &ctx, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    benchmark::DoNotOptimize(hits);
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(rays.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["hit_fraction"] = double(hits) / double(rays.size());
}
BENCHMARK(BM_EmbreePrimaryRays)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace lt

int main(int argc, char** argv) {
  lt::RetainFreedMemory();  // as the lasertwin command does
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

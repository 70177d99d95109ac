// Stripe extraction speed: each method at 640x480, 2688x480 and 2688x1620 on
// a single-stripe 8-bit frame, with 1 and 2 threads. The frame is synthetic
// (pipeline/synthetic_stripes.h): a slightly tilted and curved Gaussian stripe
// (sigma 2 px, FWHM 4.7 px, peak 200 DN) on an 8 DN background with 2 DN
// Gaussian noise, rounded to 8 bits. Run with --benchmark_repetitions=N and
// read the medians (docs/performance.md).
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "pipeline/stripe_extractor.h"
#include "pipeline/synthetic_stripes.h"

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

void BM_Extract(benchmark::State& state) {
  const auto method = lt::ExtractionMethod(state.range(0));
  const int width = int(state.range(1)), height = int(state.range(2)), threads = int(state.range(3));
  const lt::Image<uint8_t>& img = Frame(width, height);
  lt::ExtractionOptions o;
  o.method = method;
  o.threshold = 60;
  o.expected_width = 4.7;
  o.threads = threads;
  lt::StripeExtractor extractor(o);
  std::vector<lt::StripePoint> points;
  extractor.Extract(img.View(), &points);  // buffers grow once
  for (auto _ : state) {
    extractor.Extract(img.View(), &points);
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["points"] = double(points.size());
  state.SetLabel(std::string(lt::MethodName(method)) + " " + std::to_string(width) + "x" + std::to_string(height) +
                 " threads " + std::to_string(threads));
}

void Register(benchmark::internal::Benchmark* b) {
  for (int m = 0; m < 4; ++m)
    for (auto [w, h] : {std::pair{640, 480}, std::pair{2688, 480}, std::pair{2688, 1620}})
      for (int t : {1, 2}) b->Args({m, w, h, t});
  b->ArgNames({"method", "w", "h", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_Extract)->Apply(Register);

}  // namespace

BENCHMARK_MAIN();

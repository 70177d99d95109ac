// Triangulation speed: TriangulatePoints on one frame's stripe points (one
// point per row of a 2688x1620 image, 1620 points, a tilted laser plane), for a
// pinhole camera, Brown-Conrady distortion (iterative inverse) and a fisheye,
// with the world transform. Single-threaded. Run with
// --benchmark_repetitions=N and read the medians (docs/performance.md).
#include <benchmark/benchmark.h>

#include "pipeline/triangulation.h"

namespace {

lt::Camera MakeCamera(int model) {
  lt::CameraParams p;
  p.width = 2688;
  p.height = 1620;
  p.fx = p.fy = 2200;
  p.cx = 1343.5;
  p.cy = 809.5;
  if (model == 1) {
    p.distortion = lt::DistortionModel::kBrownConrady;
    p.brown_conrady = {-0.2, 0.05, 0.001, -0.0005, 0.01};
  } else if (model == 2) {
    p.distortion = lt::DistortionModel::kFisheye;
    p.fisheye = {0.05, -0.01, 0.002, 0};
  }
  return lt::Camera(p);
}

void BM_Triangulate(benchmark::State& state) {
  const int model = int(state.range(0));
  const lt::Plane sheet = lt::Plane::FromPointNormal({0, 0, 0.08}, {0.894, 0, 0.447});  // vertical stripe
  lt::Triangulator triangulator(MakeCamera(model), {sheet});
  std::vector<lt::StripePoint> points;
  for (int v = 0; v < 1620; ++v) points.push_back({1300.0 + 0.05 * v + 0.37, double(v), 4, 500, 0});
  lt::Pose world_from_cam = lt::Pose::Identity();
  world_from_cam.translation() = Eigen::Vector3d(0.1, 0.2, 0.3);
  lt::TriangulationStats stats;
  for (auto _ : state) {
    auto out = lt::TriangulatePoints(triangulator, points, world_from_cam, &stats);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["points"] = double(stats.triangulated);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(points.size()));
  static const char* names[] = {"pinhole", "brown_conrady", "fisheye"};
  state.SetLabel(names[model]);
}

BENCHMARK(BM_Triangulate)->DenseRange(0, 2)->ArgName("camera")->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();

// The subsurface cache's query, LaserEntryTree::Sum, alone (docs/performance.md):
//  - EntryTreeSum/demo: the demo's dim frame (scenes/demo/scene.json, frame 1)
//    binned to 640x480, the bench_render DimFrame640 frame;
//  - EntryTreeSum/print: scenes/print/scene.json's dim frame 241 (160x120), the
//    stripe across the second layer's beads (the heaviest of the frames tried,
//    1 230 segments);
//  - EntryTreeSum/file: the scene file named by LT_BENCH_ENTRY_SCENE (frame 1,
//    the file's resolution), when set: e.g. a finished printed part.
// Each builds the frame's cache of its first laser sheet as the renderer does
// (the chief hits' window, entry spacing mfp / 8) and sums it at every chief hit
// on a subsurface material that the cache covers and where the sum over every
// segment is not zero (the pixels near the stripe), with the hit's geometric
// normal turned to the camera and the profile of the material's colour at the
// laser's wavelength. Counters: queries, the tree's segments, ns_per_query,
// evaluated_per_query (nodes and segments evaluated, Sum's `evaluated`), and
// the accuracy the timing comes with, Sum against the sum over every segment,
// each evaluated as Sum evaluates a segment (SumOverSegments at kOpeningRatio),
// so that the difference is the error of nodes standing for their segments:
// total_rel_err, sum |Sum - exact| over sum exact, and max_rel_err, the largest
// |Sum / exact - 1| over the queries whose exact sum is at least 1% of the
// largest (a query at the edge of the profile's reach, where a node's centroid
// lies within r_max and some of its segments do not, can be off by more, on a
// sum near zero).
// Threads: one (the queries run serially).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "render/chief_rays.h"
#include "render/frame_renderer.h"
#include "render/spectrum.h"
#include "scene/embree_scene.h"
#include "scene/scene_file.h"
#include "resized_camera.h"

namespace lt {
namespace {

struct Query {
  Eigen::Vector3d p, n;
  uint32_t material;
  size_t profile;  // index into Frame::profiles
};

struct Frame {
  std::unique_ptr<EmbreeScene> embree;
  std::unique_ptr<LaserEntryTree> tree;
  std::vector<BurleyProfile> profiles;  // per material (unused where none)
  std::vector<double> r_max;
  std::vector<Query> queries;
};

// Renders `frame_index` of the scene once at one sample (which moves a printed
// part to the frame's time), traces its chief rays and builds sheet 0's cache.
Frame MakeFrame(const std::string& path, int width, int height, int64_t frame_index) {
  SceneFile scene = LoadSceneFile(path);
  scene.sensor.camera = ResizedCamera(scene.sensor.camera, width, height);  // same field of view
  Frame f;
  auto geometry = std::make_shared<SceneGeometry>(LoadSceneGeometry(scene));
  f.embree = std::make_unique<EmbreeScene>(geometry);
  RenderOverrides o;
  o.spp = 1;
  o.threads = 1;
  const RenderedFrame rendered = FrameRenderer(scene, *f.embree, o).Render(frame_index);
  const ShutterFrame& sf = rendered.shutter;
  FrameLights lights = MakeFrameLights(scene.sensor, rendered.world_from_cam, sf.laser_fraction, sf.pattern_fraction,
                                       sf.led_fraction);
  std::vector<ChiefRay> rays(size_t(width) * size_t(height));
  TraceChiefRays(*f.embree, scene.sensor.camera, rendered.world_from_cam, 0, 0, width, height, rays);
  std::vector<ChiefHit> hits(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    if (!rays[i].hit) continue;
    hits[i].valid = true;
    hits[i].p_world = rays[i].hit->position;
    Eigen::Vector3d n = rays[i].hit->geometric_normal;
    if (n.dot(rays[i].direction) > 0) n = -n;  // facing the camera
    hits[i].normal = n;
    hits[i].depth = rays[i].hit->t;
    hits[i].material = rays[i].hit->material_id;
  }
  const std::vector<Material>& materials = f.embree->geometry().materials;
  const PointEmitter* laser = nullptr;
  for (const PointEmitter& e : lights.emitters) laser = laser ? laser : (e.laser ? &e : nullptr);
  if (!laser) return f;
  // The renderer's reach (albedo 1) per material and its entry spacing.
  std::vector<double> reach(materials.size(), 0.0);
  double min_mfp = 0;
  for (size_t m = 0; m < materials.size(); ++m) {
    DiffusionProfileParams pp;
    pp.albedo = 1.0;
    pp.mean_free_path = materials[m].subsurface ? materials[m].subsurface->mean_free_path_laser_m : 1.0;
    f.profiles.emplace_back(pp);
    f.r_max.push_back(0.0);
    if (!materials[m].subsurface) continue;
    reach[m] = BurleyProfile(pp).SampleRadius(0.999);
    pp.albedo = ValueAtWavelength(materials[m].base_color, laser->laser->wavelength_m());
    f.profiles[m] = BurleyProfile(pp);
    f.r_max[m] = f.profiles[m].SampleRadius(0.999);
    if (!(min_mfp > 0) || pp.mean_free_path < min_mfp) min_mfp = pp.mean_free_path;
  }
  const SheetWindow window = SheetWindowOfHits(*laser, 0, hits, reach);
  f.tree = LaserEntryTree::Build(*f.embree, *laser, 0, window, 0.125 * min_mfp, nullptr);
  if (!f.tree) return f;
  for (const ChiefHit& h : hits) {
    if (!h.valid || !materials[h.material].subsurface) continue;
    const double r_max = f.r_max[h.material];
    if (!f.tree->Covers(h.p_world, r_max)) continue;
    if (!(f.tree->SumOverSegments(h.p_world, h.normal, h.material, f.profiles[h.material], r_max) > 0)) continue;
    f.queries.push_back({h.p_world, h.normal, h.material, h.material});
  }
  return f;
}

Frame& DemoFrame() {
  static Frame f = MakeFrame(std::string(LT_SOURCE_DIR) + "/scenes/demo/scene.json", 640, 480, 1);
  return f;
}

Frame& PrintFrame() {
  static Frame f = MakeFrame(std::string(LT_SOURCE_DIR) + "/scenes/print/scene.json", 160, 120, 241);
  return f;
}

void RunSum(benchmark::State& state, Frame& f) {
  if (!f.tree || f.queries.empty()) {
    state.SkipWithError("no cache or no query");
    return;
  }
  double total = 0;
  for (auto _ : state) {
    for (const Query& q : f.queries) {
      total += f.tree->Sum(q.p, q.n, q.material, f.profiles[q.profile], f.r_max[q.material]);
    }
  }
  benchmark::DoNotOptimize(total);
  std::vector<double> exact, sum;
  int64_t evaluated = 0;
  for (const Query& q : f.queries) {
    f.tree->Sum(q.p, q.n, q.material, f.profiles[q.profile], f.r_max[q.material], LaserEntryTree::kOpeningRatio,
                &evaluated);
    exact.push_back(f.tree->SumOverSegments(q.p, q.n, q.material, f.profiles[q.profile], f.r_max[q.material],
                                            LaserEntryTree::kOpeningRatio));
    sum.push_back(f.tree->Sum(q.p, q.n, q.material, f.profiles[q.profile], f.r_max[q.material]));
  }
  const double largest = *std::max_element(exact.begin(), exact.end());
  double max_err = 0, abs_err = 0, all = 0;
  for (size_t i = 0; i < exact.size(); ++i) {
    abs_err += std::abs(sum[i] - exact[i]);
    all += exact[i];
    if (exact[i] >= 0.01 * largest) max_err = std::max(max_err, std::abs(sum[i] / exact[i] - 1.0));
  }
  state.counters["queries"] = double(f.queries.size());
  state.counters["evaluated_per_query"] = double(evaluated) / double(f.queries.size());
  state.counters["segments"] = double(f.tree->points());
  state.counters["ns_per_query"] = benchmark::Counter(double(f.queries.size()) * 1e-9,
                                                      benchmark::Counter::kIsIterationInvariantRate |
                                                          benchmark::Counter::kInvert);
  state.counters["max_rel_err"] = max_err;
  state.counters["total_rel_err"] = abs_err / all;
}

Frame& FileFrame() {
  static Frame f = [] {
    const std::string path = std::getenv("LT_BENCH_ENTRY_SCENE");
    const CameraParams p = LoadSceneFile(path).sensor.camera.params();
    return MakeFrame(path, p.width, p.height, 1);
  }();
  return f;
}

void BM_EntryTreeSumDemo(benchmark::State& state) { RunSum(state, DemoFrame()); }
void BM_EntryTreeSumPrint(benchmark::State& state) { RunSum(state, PrintFrame()); }
BENCHMARK(BM_EntryTreeSumDemo)->Name("EntryTreeSum/demo")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(BM_EntryTreeSumPrint)->Name("EntryTreeSum/print")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void BM_EntryTreeSumFile(benchmark::State& state) { RunSum(state, FileFrame()); }

}  // namespace
}  // namespace lt

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (std::getenv("LT_BENCH_ENTRY_SCENE")) {
    benchmark::RegisterBenchmark("EntryTreeSum/file", lt::BM_EntryTreeSumFile)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

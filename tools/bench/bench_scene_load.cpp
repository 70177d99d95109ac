// Scene loading: time and peak memory to load a generated triangle mesh of 1 M
// and 10 M triangles (a 100 x 100 mm height field with normals, as one .glb), the
// glTF alone and the whole path of `lasertwin info` (scene file, glTF, Embree
// build). Also the demo scene. The meshes are written once to the temp folder
// (about 24 bytes per triangle) and removed at exit unless LT_BENCH_KEEP=1, so the
// command can be timed on them too (docs/performance.md).
//
// Peak memory: before each iteration the process's peak resident set (VmHWM) is
// reset (/proc/self/clear_refs), after it VmHWM is read: "peak_rss_MB" is the
// peak of the whole process during the load, "peak_load_MB" the part above the
// resident size before the load.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "scene/embree_scene.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_writer.h"
#include "scene/scene_file.h"

namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::temp_directory_path() / "lasertwin_bench_scene";

// kB value of a /proc/self/status line ("VmHWM:", "VmRSS:").
double StatusMb(const std::string& key) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key, 0) == 0) return std::atof(line.c_str() + key.size()) / 1024.0;
  }
  return 0;
}

void ResetPeak() { std::ofstream("/proc/self/clear_refs") << "5"; }

// An n x n vertex grid over 100 x 100 mm, z = 0.5 mm sin(x / 3 mm) cos(y / 5 mm),
// with analytic normals: 2 (n-1)^2 triangles. Returns the scene file using it.
fs::path MakeHeightField(size_t triangles) {
  const size_t n = size_t(std::ceil(std::sqrt(double(triangles) / 2.0))) + 1;
  const std::string stem = "heightfield_" + std::to_string(triangles);
  const fs::path glb = kDir / (stem + ".glb"), scene = kDir / (stem + ".json");
  if (fs::exists(glb) && fs::exists(scene)) return scene;
  fs::create_directories(kDir);
  const double size = 0.1, a = 0.5e-3, kx = 1 / 3e-3, ky = 1 / 5e-3;
  std::vector<float> p, nrm;
  p.reserve(3 * n * n);
  nrm.reserve(3 * n * n);
  for (size_t j = 0; j < n; ++j) {
    for (size_t i = 0; i < n; ++i) {
      double x = size * double(i) / double(n - 1), y = size * double(j) / double(n - 1);
      double z = a * std::sin(kx * x) * std::cos(ky * y);
      double dzdx = a * kx * std::cos(kx * x) * std::cos(ky * y), dzdy = -a * ky * std::sin(kx * x) * std::sin(ky * y);
      double len = std::sqrt(dzdx * dzdx + dzdy * dzdy + 1);
      p.insert(p.end(), {float(x), float(y), float(z)});
      nrm.insert(nrm.end(), {float(-dzdx / len), float(-dzdy / len), float(1 / len)});
    }
  }
  std::vector<uint32_t> idx;
  idx.reserve(6 * (n - 1) * (n - 1));
  for (size_t j = 0; j + 1 < n; ++j) {
    for (size_t i = 0; i + 1 < n; ++i) {
      uint32_t v = uint32_t(j * n + i);
      idx.insert(idx.end(), {v, v + 1, v + uint32_t(n) + 1, v, v + uint32_t(n) + 1, v + uint32_t(n)});
    }
  }
  {
    lt::GltfBuilder b;
    int mesh = b.AddTriangleMesh("heightfield", p, nrm, {}, idx);
    p = {};
    nrm = {};
    idx = {};
    b.AddNode("heightfield", mesh);
    b.WriteGlb(glb);
  }
  std::ofstream(scene) << R"({"objects": [{"name": "field", "gltf": ")" << glb.filename().string() << R"("}],
  "sensor": {"camera": {"resolution": [1280, 1024], "pixel_pitch_um": 4.8, "focal_length_mm": 8, "f_number": 5.6}}})";
  return scene;
}

struct Cleanup {
  ~Cleanup() {
    const char* keep = std::getenv("LT_BENCH_KEEP");
    if (!(keep && std::string(keep) == "1")) {
      std::error_code ec;
      fs::remove_all(kDir, ec);
    }
  }
} cleanup;

void Report(benchmark::State& state, double rss_before, size_t triangles) {
  state.counters["peak_rss_MB"] = StatusMb("VmHWM:");
  state.counters["peak_load_MB"] = StatusMb("VmHWM:") - rss_before;
  state.counters["triangles"] = double(triangles);
}

void BM_LoadGltf(benchmark::State& state) {
  const fs::path scene = MakeHeightField(size_t(state.range(0)));
  const fs::path glb = scene.parent_path() / (scene.stem().string() + ".glb");
  for (auto _ : state) {
    const double before = StatusMb("VmRSS:");
    ResetPeak();
    lt::GltfAsset asset = lt::LoadGltf(glb);
    benchmark::DoNotOptimize(asset.meshes.data());
    Report(state, before, asset.meshes.at(0).TriangleCount());
  }
}

// What `lasertwin info` does: scene file, glTF, materials, Embree scene.
void BM_LoadSceneAndBuildEmbree(benchmark::State& state) {
  const fs::path scene_path = MakeHeightField(size_t(state.range(0)));
  for (auto _ : state) {
    const double before = StatusMb("VmRSS:");
    ResetPeak();
    lt::SceneFile scene = lt::LoadSceneFile(scene_path);
    auto geometry = std::make_shared<const lt::SceneGeometry>(lt::LoadSceneGeometry(scene));
    lt::EmbreeScene embree(geometry);
    benchmark::DoNotOptimize(embree.handle());
    Report(state, before, embree.triangle_count());
  }
}

void BM_LoadDemoScene(benchmark::State& state) {
  const fs::path scene_path = fs::path(LT_SOURCE_DIR) / "scenes/demo/scene.json";
  for (auto _ : state) {
    lt::SceneFile scene = lt::LoadSceneFile(scene_path);
    auto geometry = std::make_shared<const lt::SceneGeometry>(lt::LoadSceneGeometry(scene));
    lt::EmbreeScene embree(geometry);
    benchmark::DoNotOptimize(embree.handle());
    state.counters["triangles"] = double(embree.triangle_count());
  }
}

BENCHMARK(BM_LoadGltf)->Arg(1'000'000)->Arg(10'000'000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_LoadSceneAndBuildEmbree)
    ->Arg(1'000'000)
    ->Arg(10'000'000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(BM_LoadDemoScene)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

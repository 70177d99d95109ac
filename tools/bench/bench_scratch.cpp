#include <benchmark/benchmark.h>
#include <chrono>
#include <cstdlib>
#include <map>
#include <iostream>
#include <algorithm>
#include "pipeline/stripe_extractor.h"
#include "render/frame_renderer.h"
#include "scene/embree_scene.h"
#include "scene/scene_file.h"
using namespace lt;
struct Demo {
  SceneFile scene; std::shared_ptr<SceneGeometry> geometry; std::unique_ptr<EmbreeScene> embree;
  Demo(int width, int height, bool sss) {
    scene = LoadSceneFile(std::string(LT_SOURCE_DIR) + "/scenes/demo/scene.json");
    scene.render.subsurface = sss; if (getenv("BOUNCES")) scene.render.max_bounces = atoi(getenv("BOUNCES"));
    CameraParams p = scene.sensor.camera.params();
    double s = double(width) / p.width; p.fx *= s, p.fy *= s; p.pixel_pitch_m /= s;
    p.cx = (width - 1) / 2.0, p.cy = (height - 1) / 2.0; p.width = width, p.height = height;
    scene.sensor.camera = Camera(p);
    geometry = std::make_shared<SceneGeometry>(LoadSceneGeometry(scene));
    embree = std::make_unique<EmbreeScene>(geometry);
  }
};
std::map<int,double> Com(const Image<float>& radiance, double peak_ref) {
  Image<float> laser(radiance.width, radiance.height, 1);
  for (int y = 0; y < radiance.height; ++y) for (int x = 0; x < radiance.width; ++x) laser.At(x, y) = radiance.At(x, y, 3);
  ExtractionOptions o; o.method = ExtractionMethod::kCom; o.axis = SearchAxis::kCols; o.threshold = 0.1 * peak_ref; o.threads = 1;
  std::map<int,double> r; for (auto& p : StripeExtractor(o).Extract(laser.View())) r[int(std::lround(p.u))] = p.v; return r;
}
int main(int argc, char** argv) {
  bool sss = !getenv("NOSSS");
  int spp = argc > 1 ? atoi(argv[1]) : 4;
  int refspp = getenv("REFSPP") ? atoi(getenv("REFSPP")) : 256;
  Demo d(640, 480, sss);
  RenderOverrides o; o.spp = refspp; o.seed = 999;
  std::map<int,double> rc; float peak = 0;
  std::string cache = std::string("/tmp/ref_") + (sss ? "sss" : "nosss") + ".txt";
  if (FILE* fp = fopen(cache.c_str(), "r")) { fscanf(fp, "%f", &peak); int u; double v; while (fscanf(fp, "%d %lf", &u, &v) == 2) rc[u] = v; fclose(fp); }
  else {
  auto ref = FrameRenderer(d.scene, *d.embree, o).Render(1);
  for (int y=0;y<480;++y) for(int x=0;x<640;++x) peak=std::max(peak, ref.radiance.At(x,y,3));
  rc = Com(ref.radiance, peak);
  FILE* fo = fopen(cache.c_str(), "w"); fprintf(fo, "%.9g\n", peak); for (auto& [u,v] : rc) fprintf(fo, "%d %.9f\n", u, v); fclose(fo); }
  o.spp = spp; o.seed = 1; o.threads = 1;
  FrameRenderer r(d.scene, *d.embree, o);
  auto c0 = std::clock(); auto f = r.Render(1); double ms = 1000.0*(std::clock()-c0)/CLOCKS_PER_SEC;
  auto mc = Com(f.radiance, peak);
  std::vector<double> e; for (auto& [u,v] : mc) { auto it = rc.find(u); if (it!=rc.end()) e.push_back(std::abs(v-it->second)); }
  std::sort(e.begin(), e.end()); double s=0; for (double x: e) s+=x*x;
  auto q=[&](double p){return e[size_t(p*(e.size()-1))];};
  if (getenv("COLS")) for (auto& [u,v] : mc) { auto it = rc.find(u); if (it!=rc.end() && std::abs(v-it->second) > 1) std::cout << "col " << u << " " << v << " ref " << it->second << "\n"; }
  std::cout << "spp " << spp << " sss " << sss << " cpu_ms " << ms << " rays " << f.stats.rays << " near " << f.stats.near_pixels
            << " n " << e.size() << "/" << rc.size() << " rms " << std::sqrt(s/e.size()) << " med " << q(0.5) << " p90 " << q(0.9) << " p99 " << q(0.99) << " max " << e.back() << "\n";
  if (getenv("PROFILE")) { int x = atoi(getenv("PROFILE")); for (int y=0;y<480;++y) { float a=0, b=f.radiance.At(x,y,3); if (b>0.001*peak) std::cout << y << " " << a/peak << " " << b/peak << "\n"; } }
}

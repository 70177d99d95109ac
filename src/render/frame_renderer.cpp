// FrameRenderer (frame_renderer.h): its set-up from the scene, the subsurface caches,
// the film's noise model and Render, which runs the passes. The per-pixel passes
// (GroundTruthPass, SamplePass) are in frame_renderer_passes.cpp; sample budgets and
// edges in frame_renderer_budgets.cpp, images in frame_renderer_images.cpp.
#include "render/frame_renderer.h"

#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/image_io.h"
#include "render/laser_entry_tree.h"
#include "render/multi_jitter.h"
#include "render/subsurface_profile.h"

namespace lt {

namespace {

// Light paths per laser sheet and frame at most (render.light_paths times spp).
constexpr int64_t kMaxLightPaths = int64_t(1) << 28;
// Entry points of the frame's subsurface cache this fraction of the smallest
// laser mean free path apart (render/laser_entry_tree.h).
constexpr double kEntrySpacingPerMeanFreePath = 0.125;
// A moving scanner's frame takes the cache of its mid-exposure pose when no
// surface it sees moves by more than this fraction of the entry spacing from
// the middle of the exposure to its start or end (1/32 of the smallest mean
// free path: 11 um for the demo's PLA; a dim frame of 100 us at 50 mm/s moves
// 2.5 um). Beyond that the exposure is cut into time slices that each move
// within the bound, each with the caches of the pose of its middle, at most
// kMaxCacheSlices of them (beyond: Monte Carlo).
constexpr double kCacheMotionPerSpacing = 0.25;
constexpr int kMaxCacheSlices = 16;

double Ms(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// How far a scene point within `reach_m` of the camera moves relative to the
// scanner between times t_a and t_b (a bound: the translation plus the
// rotation angle times the reach).
double Displacement(const Motion& motion, double t_a, double t_b, double reach_m) {
  const Pose a_from_b = WorldFromCamAt(motion, t_a).inverse() * WorldFromCamAt(motion, t_b);
  const double angle = Eigen::AngleAxisd(a_from_b.linear()).angle();
  return a_from_b.translation().norm() + std::abs(angle) * reach_m;
}

// The same between the middle of [t0, t1] and its start or end, the larger.
double ExposureDisplacement(const Motion& motion, double t0, double t1, double reach_m) {
  const double mid = 0.5 * (t0 + t1);
  return std::max(Displacement(motion, mid, t0, reach_m), Displacement(motion, mid, t1, reach_m));
}

// The fewest equal parts of [t0, t1] (at most kMaxCacheSlices) in each of
// which no point within reach_m moves by more than bound_m from the part's
// middle to its ends; 0 when kMaxCacheSlices parts still move more.
int CacheSlices(const Motion& motion, double t0, double t1, double reach_m, double bound_m) {
  const double whole = ExposureDisplacement(motion, t0, t1, reach_m);
  if (whole <= bound_m) return 1;
  // Uniform motion needs ceil(whole / bound) parts; start there.
  for (int k = int(std::clamp(std::ceil(whole / bound_m), 2.0, double(kMaxCacheSlices + 1))); k <= kMaxCacheSlices;
       ++k) {
    bool within = true;
    for (int s = 0; s < k && within; ++s) {
      const double a = t0 + (t1 - t0) * s / k, b = s + 1 == k ? t1 : t0 + (t1 - t0) * (s + 1) / k;
      within = ExposureDisplacement(motion, a, b, reach_m) <= bound_m;
    }
    if (within) return k;
  }
  return 0;
}

// Photo-electrons per joule at wavelength lambda in the sensor's most sensitive channel.
double ElectronsPerJoule(const ImageSensor& sensor, double lambda) {
  double qe = 0;
  for (int k = 0; k < 3; ++k) qe = std::max(qe, sensor.QuantumEfficiency(k, lambda));
  return qe * PhotonsFromEnergy(1.0, lambda);
}

template <typename F>
void InArena(int threads, F&& f) {
  if (threads > 0) {
    tbb::task_arena arena(threads);
    arena.execute(f);
  } else {
    f();
  }
}

}  // namespace

bool FrameRenderer::IsStaticWithin(const Motion& motion, double t0, double t1) {
  Pose a = WorldFromCamAt(motion, t0), b = WorldFromCamAt(motion, t1);
  return a.isApprox(b, 1e-15) || (a.matrix() - b.matrix()).cwiseAbs().maxCoeff() == 0.0;
}

FrameRenderer::FrameRenderer(const SceneFile& scene, const EmbreeScene& embree, const RenderOverrides& overrides)
    : FrameRenderer(scene, embree, nullptr, overrides) {}

FrameRenderer::FrameRenderer(const SceneFile& scene, EmbreeScene& embree, const RenderOverrides& overrides)
    : FrameRenderer(scene, embree, &embree, overrides) {}

FrameRenderer::FrameRenderer(const SceneFile& scene, const EmbreeScene& embree, EmbreeScene* mutable_embree,
                             const RenderOverrides& overrides)
    : scene_(scene),
      embree_(embree),
      mutable_embree_(mutable_embree),
      spp_(overrides.spp.value_or(scene.render.spp)),
      edge_spp_(spp_ * scene.render.edge_spp_factor),
      threads_(overrides.threads.value_or(scene.render.threads)),
      seed_(overrides.seed.value_or(scene.seed)),
      layout_(MakeEmitterLayout(scene.sensor)) {
  if (scene.print) {
    if (!mutable_embree_ || !mutable_embree_->mutable_geometry()) {
      throw std::invalid_argument(
          "FrameRenderer: the scene has a printed part; build the EmbreeScene from mutable geometry and pass it "
          "non-const");
    }
    print_ = std::make_unique<PrintedPart>(std::get<GcodeMotion>(scene.motion), *scene.print,
                                           embree.geometry().print_meshes);
  }
  if (scene_.environment.kind == Environment::Kind::kMap) {
    environment_map_ = scene_.environment.map ? *scene_.environment.map : ReadImageFloat(scene_.environment.exr);
  }
  PathTracerOptions options;
  options.max_bounces = scene.render.max_bounces;
  options.russian_roulette_depth = scene.render.russian_roulette_depth;
  options.subsurface = scene.render.subsurface;
  tracer_ = std::make_unique<PathTracer>(
      embree, scene.environment,
      scene.environment.kind == Environment::Kind::kMap ? &environment_map_ : nullptr, options, layout_.channels);
  const Camera& cam = scene.sensor.camera;
  radiance_to_irradiance_ = Image<float>(cam.width(), cam.height(), 1);
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x)
      radiance_to_irradiance_.At(x, y) = float(cam.RadianceToIrradiance(Eigen::Vector2d(x, y)));
  max_radiance_to_irradiance_ =
      *std::max_element(radiance_to_irradiance_.pixels.begin(), radiance_to_irradiance_.pixels.end());
  if (scene_.environment.kind == Environment::Kind::kMap) {
    for (float v : environment_map_.pixels) max_environment_radiance_ = std::max(max_environment_radiance_, double(v));
    max_environment_radiance_ *= scene_.environment.scale;
  } else {
    max_environment_radiance_ = scene_.environment.radiance.maxCoeff();
  }
  for (const Material& m : embree.geometry().materials) {
    if (m.emissive.maxCoeff() > 0) has_emission_ = true;
    max_emission_ = std::max(max_emission_, double(m.emissive.maxCoeff()));
    double reach = 0, half = 0;
    if (m.subsurface && scene.render.subsurface) {
      DiffusionProfileParams p;
      p.albedo = 1.0;  // the widest profile for this mean free path
      p.mean_free_path = m.subsurface->mean_free_path_laser_m;
      half = BurleyProfile(p).SampleRadius(0.5);
      reach = BurleyProfile(p).SampleRadius(0.999);
      if (!(min_subsurface_mfp_m_ > 0) || p.mean_free_path < min_subsurface_mfp_m_) {
        min_subsurface_mfp_m_ = p.mean_free_path;
      }
    }
    subsurface_reach_m_.push_back(reach);
    subsurface_half_m_.push_back(half);
  }
}

FrameRenderer::~FrameRenderer() = default;

std::vector<std::unique_ptr<LaserEntryTree>> FrameRenderer::BuildEntryTrees(std::span<const ChiefHit> hits,
                                                                           FrameLights* lights, FrameStats* stats,
                                                                           double window_extra_m) const {
  std::vector<std::unique_ptr<LaserEntryTree>> trees;
  if (!(min_subsurface_mfp_m_ > 0) || !scene_.render.subsurface_cache) return trees;
  for (PointEmitter& e : lights->emitters) {
    if (!e.laser) continue;
    e.entry_trees.assign(size_t(e.channels), nullptr);
    for (int k = 0; k < e.channels; ++k) {
      const SheetWindow window = SheetWindowOfHits(e, k, hits, subsurface_reach_m_, window_extra_m);
      trees.push_back(
          LaserEntryTree::Build(embree_, e, k, window, kEntrySpacingPerMeanFreePath * min_subsurface_mfp_m_,
                                &stats->rays));
      e.entry_trees[size_t(k)] = trees.back().get();
    }
  }
  return trees;
}

std::vector<std::unique_ptr<LaserEntryTree>> FrameRenderer::BuildSlicedEntryTrees(std::span<const ChiefHit> hits,
                                                                                 const ShutterFrame& sf, int slices,
                                                                                 double reach_m, FrameLights* lights,
                                                                                 FrameStats* stats) const {
  std::vector<std::unique_ptr<LaserEntryTree>> trees;
  const double t0 = sf.t_start_s, t1 = sf.t_end_s, mid = 0.5 * (t0 + t1);
  size_t points = 0;
  lights->entry_tree_slices.assign(size_t(slices), {});
  for (int s = 0; s < slices; ++s) {
    const double a = t0 + (t1 - t0) * s / slices, b = s + 1 == slices ? t1 : t0 + (t1 - t0) * (s + 1) / slices;
    // The lasers move with the scanner: the slice's sheets cast from the pose
    // of its middle. Its camera sees the surface up to `extra` away from the
    // mid-exposure chief hits, which the sheets' windows take in.
    FrameLights at = MakeFrameLights(scene_.sensor, WorldFromCamAt(scene_.motion, 0.5 * (a + b)), sf.laser_fraction,
                                     sf.pattern_fraction, sf.led_fraction);
    const double extra =
        std::max(Displacement(scene_.motion, mid, a, reach_m), Displacement(scene_.motion, mid, b, reach_m));
    std::vector<std::unique_ptr<LaserEntryTree>> built = BuildEntryTrees(hits, &at, stats, extra);
    for (const auto& tree : built) points += tree ? tree->points() : 0;
    if (points > LaserEntryTree::kMaxPoints) {  // too large all together: Monte Carlo
      lights->entry_tree_slices.clear();
      return {};
    }
    for (const PointEmitter& e : at.emitters) lights->entry_tree_slices[size_t(s)].push_back(e.entry_trees);
    for (auto& tree : built) trees.push_back(std::move(tree));
  }
  return trees;
}

SampleNoise FrameRenderer::MakeSampleNoise(const ShutterFrame& sf, FilmOptions* film_options) const {
  // The film's tracked value: photo-electrons at the pixel with the largest
  // radiance-to-irradiance factor (the most sensitive channel of each band and
  // of the lasers' wavelengths, so that the noise is never overestimated).
  const ImageSensor& sensor = scene_.sensor.image_sensor;
  const double joules = max_radiance_to_irradiance_ * scene_.sensor.camera.pixel_area_m2() * sf.exposure_s;
  for (int c = 0; c < 3; ++c) {
    film_options->rgb_weights[c] =
        float(joules * ElectronsPerJoule(sensor, sensor.params().band_wavelength_m[size_t(c)]));
  }
  double laser = 0;
  for (int g = 0; g < layout_.groups; ++g)
    laser = std::max(laser, ElectronsPerJoule(sensor, layout_.group_wavelength_m[size_t(g)]));
  film_options->laser_weight = float(joules * laser);
  const double gain = sensor.SystemGain(sf.analog_gain_db);
  const double dark = sensor.params().dark_noise_e;
  SampleNoise noise;
  noise.fraction = max_radiance_to_irradiance_ > 0 ? scene_.render.adaptive_noise : 0.0;
  noise.radiance_to_irradiance = &radiance_to_irradiance_;
  noise.inverse_max_radiance_to_irradiance = max_radiance_to_irradiance_ > 0 ? 1.0 / max_radiance_to_irradiance_ : 0.0;
  noise.read_variance_e2 = dark * dark + (gain > 0 ? 1.0 / (12.0 * gain * gain) : 0.0);
  return noise;
}

RenderedFrame FrameRenderer::Render(int64_t frame_index) const {
  auto t0 = std::chrono::steady_clock::now();
  const SensorRig& rig = scene_.sensor;
  const Camera& cam = rig.camera;
  const int w = cam.width(), h = cam.height();
  RenderedFrame out;
  out.shutter = rig.shutter.Frame(frame_index, seed_);
  const ShutterFrame& sf = out.shutter;
  out.world_from_cam = WorldFromCamAt(scene_.motion, 0.5 * (sf.t_start_s + sf.t_end_s));
  if (print_) {
    const PrintUpdate u = print_->UpdateTo(*mutable_embree_, 0.5 * (sf.t_start_s + sf.t_end_s));
    out.stats.print_chunks_rebuilt = u.chunks_rebuilt;
    out.stats.print_triangles_rebuilt = u.triangles_rebuilt;
    out.stats.print_triangles = u.triangles;
  }
  FrameLights lights =
      MakeFrameLights(rig, out.world_from_cam, sf.laser_fraction, sf.pattern_fraction, sf.led_fraction);
  // Broadband light needs every pixel sampled only when it can show in the image:
  // an LED, or environment / emission whose brightest radiance would give at
  // least half a digital number (a white surface cannot reflect more radiance
  // than the brightest light it sees).
  bool broadband = lights.led.has_value();
  if (!broadband && (tracer_->has_environment() || has_emission_)) {
    double l_max = std::max(max_environment_radiance_, max_emission_);
    double energy = l_max * max_radiance_to_irradiance_ * cam.pixel_area_m2() * sf.exposure_s;
    double electrons = 0;
    for (int c = 0; c < 3; ++c) {
      double lambda = rig.image_sensor.params().band_wavelength_m[size_t(c)];
      electrons = std::max(electrons, energy * ElectronsPerJoule(rig.image_sensor, lambda));
    }
    broadband = electrons * rig.image_sensor.SystemGain(sf.analog_gain_db) >= 0.5;
  }

  FilmOptions film_options;
  film_options.width = w;
  film_options.height = h;
  film_options.laser_sheets = layout_.channels;
  SampleNoise noise;
  if (scene_.render.adaptive_sampling) noise = MakeSampleNoise(sf, &film_options);
  Film film(film_options);
  std::vector<ChiefHit> chief_hits;
  std::vector<std::unique_ptr<LaserEntryTree>> entry_trees;
  // Laser light reflected on from grazing incidence comes from light paths
  // (render/path_tracer_light_paths.cpp), each at its own time of the exposure
  // in a frame where the scanner moves.
  const bool is_static = IsStaticWithin(scene_.motion, sf.t_start_s, sf.t_end_s);
  const bool has_laser = std::any_of(lights.emitters.begin(), lights.emitters.end(),
                                     [](const PointEmitter& e) { return e.laser != nullptr; });
  const bool fisheye_lens = !cam.is_pinhole() && cam.distortion_model() == DistortionModel::kFisheye;
  lights.grazing_by_light_paths =
      has_laser && scene_.render.light_paths > 0 && scene_.render.max_bounces > 0 && !fisheye_lens;
  Image<float> splat;
  FrameStats::PassTimes& pass_ms = out.stats.pass_ms;
  std::chrono::steady_clock::time_point last;
  auto lap = [&last](double* ms) {  // adds the time since the last lap to *ms
    const auto now = std::chrono::steady_clock::now();
    *ms += Ms(last, now);
    last = now;
  };
  InArena(threads_, [&] {
    Image<uint8_t> reach;
    last = std::chrono::steady_clock::now();
    GroundTruthPass(out.world_from_cam, lights, &out, &chief_hits, &reach);
    lap(&pass_ms.chief_rays);
    // A moving frame: the farthest surface the camera sees (how far a turn moves it).
    double reach_m = 0;
    if (!is_static)
      for (const ChiefHit& c : chief_hits) reach_m = c.valid ? std::max(reach_m, c.depth) : reach_m;
    // The subsurface cache holds the lit surface of the mid-exposure pose: in
    // a frame where the scanner holds still, or moves (relative to every
    // surface it sees) by less than kCacheMotionPerSpacing of the cache's
    // entry spacing, a shift far below the profile's scale whose first-order
    // effect cancels about the middle of the exposure. A frame that moves more
    // takes one cache per time slice that moves that little (CacheSlices).
    if (is_static) {
      entry_trees = BuildEntryTrees(chief_hits, &lights, &out.stats);
      out.stats.entry_tree_slices = entry_trees.empty() ? 0 : 1;
    } else if (has_laser && min_subsurface_mfp_m_ > 0 && scene_.render.subsurface_cache) {
      const int slices = CacheSlices(scene_.motion, sf.t_start_s, sf.t_end_s, reach_m,
                                     kCacheMotionPerSpacing * kEntrySpacingPerMeanFreePath * min_subsurface_mfp_m_);
      if (slices == 1) entry_trees = BuildEntryTrees(chief_hits, &lights, &out.stats);
      if (slices > 1) entry_trees = BuildSlicedEntryTrees(chief_hits, sf, slices, reach_m, &lights, &out.stats);
      out.stats.entry_tree_slices = entry_trees.empty() ? 0 : slices;
    }
    lap(&pass_ms.entry_trees);
    const Image<uint8_t> budget =
        SampleBudgets(reach, chief_hits, broadband || !scene_.render.adaptive_sampling, &out);
    for (uint8_t b : budget.pixels) out.stats.edge_pixels += b == kEdgeBudget;
    lap(&pass_ms.budgets);
    SamplePass(out, lights, budget, noise, &film, &out.stats);
    lap(&pass_ms.samples);
    if (lights.grazing_by_light_paths) {
      const int64_t paths = std::min<int64_t>(int64_t(scene_.render.light_paths) * spp_, kMaxLightPaths);
      splat = Image<float>(w, h, std::max(layout_.channels, 1), 0.0f);
      TraceStats ts;
      ExposureMotion motion{sf.t_start_s, sf.t_end_s, [this](double t) { return WorldFromCamAt(scene_.motion, t); },
                            is_static ? 0.0 : ExposureDisplacement(scene_.motion, sf.t_start_s, sf.t_end_s, reach_m)};
      tracer_->TraceLightPaths(lights, cam, out.world_from_cam, paths, seed_, frame_index, &splat, &ts,
                               is_static ? nullptr : &motion);
      out.stats.rays += ts.rays;
      for (const PointEmitter& e : lights.emitters) out.stats.light_paths += e.laser ? paths * e.channels : 0;
    }
    lap(&pass_ms.light_paths);
  });
  for (float v : out.near_mask.pixels) out.stats.near_pixels += v > 0;

  InArena(threads_, [&] {
    RadianceFromFilm(film, splat, lights, frame_index, &out);
    out.raw = rig.image_sensor.Expose(ExposureOf(out), seed_, uint64_t(frame_index));
  });
  lap(&pass_ms.film_and_sensor);
  auto t1 = std::chrono::steady_clock::now();
  out.stats.render_ms = Ms(t0, t1);

  // Exact stripe centres, for frames the lasers light.
  out.axis = ChooseScanAxis(rig.lasers);
  if (sf.laser_fraction > 0 && !rig.lasers.empty()) {
    InArena(threads_, [&] {
      out.centers = ComputeStripeCenters(embree_, cam, rig.lasers, out.world_from_cam, out.axis, {}, &chief_hits);
    });
  }
  out.stats.ground_truth_ms = Ms(t1, std::chrono::steady_clock::now());
  return out;
}

}  // namespace lt

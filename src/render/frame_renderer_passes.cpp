// The per-pixel passes of FrameRenderer::Render (frame_renderer.h): pass 1, the ground
// truth, chief hits and each pixel's Reach (GroundTruthPass), and the sample pass
// that traces the camera's paths into the film (SamplePass). The renderer's set-up,
// subsurface caches and Render itself are in frame_renderer.cpp.
#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "render/chief_rays.h"
#include "render/frame_renderer.h"
#include "render/multi_jitter.h"

namespace lt {

namespace {

constexpr uint64_t kPixelSamplePurpose = 0x504958454c53414dull;  // camera samples
constexpr uint64_t kPixelPatternPurpose = 0x504958454c504154ull;  // multi-jitter pattern of a pixel
constexpr uint64_t kLensPatternPurpose = 0x4c454e5350415454ull;   // multi-jitter pattern of its lens points
constexpr uint64_t kTimePatternPurpose = 0x54494d4550415454ull;   // of its times (moving scanner)
constexpr int kTile = 16;
constexpr double kNearSigmas = 8.0;
// The sheet itself (Reach::kInSheet): within this many of its sigmas (its light
// there is above 1.1% of the peak's) and two pixel footprints.
constexpr double kSheetSigmas = 3.0;

Ray WorldRay(const Pose& world_from_cam, const CameraRay& r) {
  Ray ray;
  ray.origin = world_from_cam * r.origin;
  ray.direction = world_from_cam.linear() * r.direction;
  return ray;
}

}  // namespace

void FrameRenderer::GroundTruthPass(const Pose& world_from_cam, const FrameLights& lights, RenderedFrame* out,
                                    std::vector<ChiefHit>* hits, Image<uint8_t>* reach) const {
  const Camera& cam = scene_.sensor.camera;
  const int w = cam.width(), h = cam.height();
  GroundTruthBuffers& gt = out->gt;
  gt.depth = Image<float>(w, h, 1, 0.0f);
  gt.normal = Image<float>(w, h, 3, 0.0f);
  gt.instance = Image<float>(w, h, 1, -1.0f);
  gt.material = Image<float>(w, h, 1, -1.0f);
  *reach = Image<uint8_t>(w, h, 1, kFar);
  hits->assign(size_t(w) * size_t(h), ChiefHit{});
  const Pose cam_from_world = world_from_cam.inverse();
  const double footprint_per_m = cam.pixel_pitch_m() / cam.image_distance_m();  // metres per pixel per metre depth
  // A pixel's chief hit, ground truth, and Reach.
  auto shade = [&](int x, int y, const ChiefRay& chief_ray) {
    if (!chief_ray.hit) return;
    const Hit& hit = *chief_ray.hit;
    ChiefHit& chief = (*hits)[size_t(y) * size_t(w) + size_t(x)];
    chief.valid = true;
    chief.p_world = hit.position;
    chief.normal = hit.geometric_normal;
    chief.depth = hit.t * chief_ray.direction.norm();
    chief.material = hit.material_id;
    Eigen::Vector3d p_cam = cam_from_world * hit.position;
    Eigen::Vector3d n = cam_from_world.linear() * hit.shading_normal;
    if (n.dot(p_cam) > 0) n = -n;
    gt.depth.At(x, y) = float(p_cam.z());
    for (int c = 0; c < 3; ++c) gt.normal.At(x, y, c) = float(n[c]);
    gt.instance.At(x, y) = float(hit.instance_id);
    gt.material.At(x, y) = float(hit.material_id);
    // Can an emitter's beam, or the glow it makes below the surface, reach the
    // neighbourhood of this point?
    double distance = (hit.position - world_from_cam.translation()).norm();
    uint8_t& r_class = reach->At(x, y);
    for (const PointEmitter& e : lights.emitters) {
      if (e.pattern) {
        r_class = kInSheet;
        break;
      }
      Eigen::Vector3d p_proj = e.projector_from_world * hit.position;
      double r = p_proj.norm();
      if (!(r > 0)) continue;
      const uint32_t m = hit.material_id;
      const double footprints = 2.0 * distance * footprint_per_m / r;
      const double sigma = e.laser->SheetSigma(r);
      const double sheet = kSheetSigmas * sigma + footprints;
      const double beam = kNearSigmas * sigma + footprints + subsurface_half_m_[m] / r;
      const double glow = subsurface_reach_m_[m] / r;
      for (int k = 0; k < e.channels && r_class != kInSheet; ++k) {
        const double offset = std::abs(e.laser->SheetOffsetAngle(k, p_proj));
        if (offset <= sheet) r_class = kInSheet;
        else if (offset <= beam) r_class = std::max<uint8_t>(r_class, kInBeam);
        else if (offset <= beam + glow) r_class = std::max<uint8_t>(r_class, kInGlow);
      }
      if (r_class == kInSheet) break;
    }
  };
  // Fixed tiles, so that the chief rays' packets do not depend on the threads.
  const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
  tbb::enumerable_thread_specific<uint64_t> rays(0);
  tbb::enumerable_thread_specific<std::vector<ChiefRay>> tile_rays;
  tbb::parallel_for(0, tiles_x * tiles_y, [&](int tile) {
    const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
    const int x1 = std::min(w, x0 + kTile), y1 = std::min(h, y0 + kTile);
    std::vector<ChiefRay>& chief_rays = tile_rays.local();
    chief_rays.resize(size_t(x1 - x0) * size_t(y1 - y0));
    rays.local() += TraceChiefRays(embree_, cam, world_from_cam, x0, y0, x1, y1, chief_rays);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) shade(x, y, chief_rays[size_t(y - y0) * size_t(x1 - x0) + size_t(x - x0)]);
  });
  for (uint64_t r : rays) out->stats.rays += r;
}

void FrameRenderer::SamplePass(const RenderedFrame& frame, const FrameLights& fixed_lights,
                               const Image<uint8_t>& budget, const SampleNoise& noise, Film* film,
                               FrameStats* stats) const {
  const Camera& cam = scene_.sensor.camera;
  const ShutterFrame& sf = frame.shutter;
  const bool moving = !IsStaticWithin(scene_.motion, sf.t_start_s, sf.t_end_s);
  // Batches of a pixel's samples: one of spp, or (adaptive) a first batch and
  // then batches that double the count, each stratified on its own: the pixel
  // position and, by a second pattern of its own, the lens point (a defocused
  // stripe finer than its blur moves across the pixel with the lens point; iid
  // lens points made it the noisiest light on the demo's print bed). With the
  // adaptive stop, every pixel first takes its first batch; then each takes the
  // count its neighbours' first batches call for (SampleNoise::TargetCount).
  // The first batch is min(spp, max(4, spp / 16)) in a beam, where it samples
  // the stripe's sharp profile across the pixel, and 2 in the glow beyond, the
  // least that estimates a variance.
  // A beam pixel at a geometric edge takes edge_spp_ samples, all of them: its
  // first batch is a beam's, and its count is not the neighbours' to decide.
  const bool adaptive = noise.fraction > 0;
  const int beam_first_batch = adaptive ? std::min(spp_, std::max(4, spp_ / 16)) : spp_;
  const int glow_first_batch = adaptive ? std::min(spp_, 2) : spp_;
  auto has_budget = [&](int x, int y) { return budget.At(x, y) != kOneSample; };
  auto first_batch_of = [&](int x, int y) {
    switch (budget.At(x, y)) {
      case kGlowBudget: return glow_first_batch;
      case kEdgeBudget: return adaptive ? beam_first_batch : edge_spp_;
      default: return beam_first_batch;
    }
  };
  tbb::enumerable_thread_specific<TraceStats> tstats;
  tbb::enumerable_thread_specific<uint64_t> tsamples(0);
  // Samples of pixel (x, y) from its film count up to `target`.
  auto sample_pixel = [&](int x, int y, int target, std::vector<float>& mono, TraceStats& ts, uint64_t& ns) {
    const bool full = has_budget(x, y);
    const uint64_t pixel = uint64_t(y) * uint64_t(cam.width()) + uint64_t(x);
    int taken = int(film->SampleCount(x, y));
    const int first_batch = first_batch_of(x, y);
    int batch = 0;  // batch b > 0 starts at first_batch * 2^(b - 1)
    for (int start = first_batch; start <= taken && batch < 31; start *= 2) ++batch;
    for (; taken < target; ++batch) {
      const int n = std::min(batch == 0 ? first_batch : taken, target - taken);
      const uint32_t pattern =
          uint32_t(HashKey(seed_, uint64_t(sf.index), pixel, kPixelPatternPurpose, uint64_t(batch)));
      const uint32_t lens_pattern =
          uint32_t(HashKey(seed_, uint64_t(sf.index), pixel, kLensPatternPurpose, uint64_t(batch)));
      const uint32_t time_pattern =
          moving ? uint32_t(HashKey(seed_, uint64_t(sf.index), pixel, kTimePatternPurpose, uint64_t(batch))) : 0;
      for (int i = 0; i < n; ++i) {
        const int s = taken + i;
        Rng rng = Rng::For(seed_, uint64_t(sf.index), pixel, uint64_t(s), kPixelSamplePurpose);
        const Eigen::Vector2d j = MultiJitter2D(uint32_t(i), uint32_t(n), pattern);
        Eigen::Vector2d lens(0.5, 0.5);
        if (!cam.is_pinhole()) lens = MultiJitter2D(uint32_t(i), uint32_t(n), lens_pattern);
        Pose world_from_cam = frame.world_from_cam;
        FrameLights moving_lights;
        const FrameLights* lights = &fixed_lights;
        if (moving) {
          // The sample's time in the exposure, 0..1, stratified over the batch
          // (a pattern of its own): each time slice's caches (below) take
          // their share of the pixel's samples.
          const double u = MultiJitter2D(uint32_t(i), uint32_t(n), time_pattern).x();
          double t = sf.t_start_s + u * (sf.t_end_s - sf.t_start_s);
          world_from_cam = WorldFromCamAt(scene_.motion, t);
          moving_lights = MakeFrameLights(scene_.sensor, world_from_cam, sf.laser_fraction, sf.pattern_fraction,
                                          sf.led_fraction);
          // The caches of the time slice holding t, or the mid-exposure ones
          // (Render: the scanner moves by a fraction of their entry spacing),
          // where the frame has them.
          const auto& slices = fixed_lights.entry_tree_slices;
          const size_t slice = std::min(slices.size(), size_t(u * double(slices.size())) + 1) - 1;
          for (size_t e = 0; e < moving_lights.emitters.size() && e < fixed_lights.emitters.size(); ++e)
            moving_lights.emitters[e].entry_trees =
                slices.empty() ? fixed_lights.emitters[e].entry_trees : slices[slice][e];
          moving_lights.grazing_by_light_paths = fixed_lights.grazing_by_light_paths;
          lights = &moving_lights;
        }
        auto cam_ray = cam.GenerateRay(Eigen::Vector2d(x - 0.5 + j.x(), y - 0.5 + j.y()), lens);
        Eigen::Vector3f rgb = Eigen::Vector3f::Zero();
        std::fill(mono.begin(), mono.end(), 0.0f);
        if (cam_ray) tracer_->Trace(WorldRay(world_from_cam, *cam_ray), *lights, rng, &rgb, mono, &ts, full);
        film->AddSample(x, y, rgb, mono);
        ++ns;
      }
      taken += n;
    }
  };
  // One pass over the image; target(x, y) is the pixel's count after it.
  auto pass = [&](auto&& target) {
    tbb::parallel_for(
        tbb::blocked_range2d<int>(0, cam.height(), kTile, 0, cam.width(), kTile), [&](const auto& range) {
          TraceStats& ts = tstats.local();
          uint64_t& ns = tsamples.local();
          std::vector<float> mono(size_t(layout_.channels));
          for (int y = range.rows().begin(); y < range.rows().end(); ++y)
            for (int x = range.cols().begin(); x < range.cols().end(); ++x) sample_pixel(x, y, target(x, y), mono, ts, ns);
        });
  };
  pass([&](int x, int y) { return has_budget(x, y) ? first_batch_of(x, y) : 1; });
  if (adaptive && (std::min(beam_first_batch, glow_first_batch) < spp_ || edge_spp_ > beam_first_batch)) {
    // Decided for every pixel from the film after the first pass, before any
    // pixel takes more: the same counts whatever the threads' order.
    Image<int32_t> target(cam.width(), cam.height(), 1, 1);
    tbb::parallel_for(tbb::blocked_range<int>(0, cam.height()), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < cam.width(); ++x) {
          if (budget.At(x, y) == kEdgeBudget) {
            target.At(x, y) = edge_spp_;
          } else if (has_budget(x, y)) {
            target.At(x, y) = noise.TargetCount(*film, x, y, first_batch_of(x, y), spp_, has_budget);
          }
        }
    });
    pass([&](int x, int y) { return target.At(x, y); });
  }
  for (const auto& t : tstats) stats->rays += t.rays;
  for (uint64_t s : tsamples) stats->samples += s;
}

}  // namespace lt

// Renders one frame of a scene: the camera image as the sensor delivers it, the
// radiance behind it, and the frame's ground truth.
//
// Passes:
//  1. Chief rays through every pixel centre at mid-exposure give the per-pixel
//     ground truth (depth, normal, instance, material) and decide, cheaply and
//     geometrically, which pixels a laser sheet can reach. A pixel is in a beam
//     when its surface point lies within 8 sigma of a sheet's plane, plus the
//     pixel's footprint and the radius holding half the energy of its own
//     material's subsurface profile (light that enters a surface leaves it only
//     from the same material), dilated by the defocus blur and by one pixel; it is
//     in the glow when it lies within the radius holding 99.9% of that energy.
//     Other pixels need one sample; pixels in a beam or a glow get the budget
//     ("near", RenderedFrame::near_mask). When broadband light shows in the image
//     (the LED, or environment and emission bright enough for half a digital
//     number), every pixel gets the full budget. With render.adaptive_noise > 0 a
//     pixel with the budget takes its samples in batches (a first of
//     min(spp, max(4, spp/16)) in a beam, where it samples the stripe's sharp
//     profile across the pixel, and of 2 in a glow, then batches that double its
//     count, each stratified) and stops once the Monte Carlo standard error of its
//     mean is below that fraction of the sensor's temporal noise at its signal
//     (render/sample_noise.h). A beam pixel within kEdgeDilation pixels of a
//     geometric edge (two neighbouring chief hits on surfaces that meet at more
//     than kCreaseDegrees, or one off the other's plane by more than a pixel's
//     footprint, or a hit beside a miss), and as near the sheet itself (3
//     sigma, not the beam's 8 and its subsurface radius), takes
//     render.edge_spp_factor times spp,
//     all of them: where the stripe crosses an edge, the laser's reflection off
//     one face onto the other makes glints finer than a pixel, rare bright paths
//     that a first batch does not reveal.
//  2. Per laser sheet, the laser light entering subsurface materials over the
//     fan angles the camera sees at mid-exposure, cast once and kept in a tree
//     (render/laser_entry_tree.h), so that every path vertex on such a material
//     sums it without noise. A scanner that moves during the exposure by more
//     than a small fraction of the cache's entry spacing gets one tree per time
//     slice of the exposure, each cast at the pose of the slice's middle, the
//     slices as many as keep that bound (at most 16; beyond, Monte Carlo).
//  3. Path samples (render/path_tracer.h), stratified over the pixel, the lens
//     aperture (thin lens only) and the exposure time (moving scanner only),
//     accumulated in the film. Every random number comes from
//     Rng::For(seed, frame, pixel, sample), so frames are bit-identical whatever
//     the thread count. Then light paths from the lasers carry the laser light
//     that surfaces meet at grazing incidence and reflect on, splatted to the
//     camera (render/path_tracer_light_paths.cpp); in a moving frame each at its
//     own time, with the lasers and the camera posed then.
//  4. Radiance -> sensor irradiance (Camera::RadianceToIrradiance) -> energy per
//     pixel over the exposure -> EMVA 1288 image sensor -> digital numbers.
//  5. Exact stripe centres by ray casting (render/stripe_truth.h).
//
// A scene with a printed part ("print", scene/printed_part.h) needs the renderer
// built on a mutable EmbreeScene: before each frame it brings the part to the
// frame's mid-exposure time (the time of the frame's world_from_cam; the bead
// under way grows by only v * exposure / 2 either side of it, well under the
// pixel footprint at print speeds), rebuilding only the chunks that changed. Such
// a renderer must not render two frames at once.
#pragma once

#include <chrono>
#include <memory>

#include "core/image.h"
#include "render/film.h"
#include "render/frame_lights.h"
#include "render/laser_entry_tree.h"
#include "render/path_tracer.h"
#include "render/sample_noise.h"
#include "render/stripe_truth.h"
#include "scene/embree_scene.h"
#include "scene/printed_part.h"
#include "scene/scene_file.h"

namespace lt {

struct RenderOverrides {
  std::optional<int> spp;
  std::optional<int> threads;
  std::optional<uint64_t> seed;
};

struct GroundTruthBuffers {
  Image<float> depth;     // camera z (m) of the surface seen by the pixel centre; 0 where nothing is hit
  Image<float> normal;    // 3 channels: unit normal in the camera frame, facing the camera; 0 where nothing
  Image<float> instance;  // instance id, -1 where nothing is hit
  Image<float> material;  // material id, -1 where nothing is hit
  Image<float> plane;     // laser sheet (global plane index) that lights the pixel most, -1 where unlit
};

struct FrameStats {
  uint64_t rays = 0;
  uint64_t samples = 0;
  int64_t near_pixels = 0;
  int64_t edge_pixels = 0;  // of them, beam pixels at a geometric edge (render.edge_spp_factor)
  int64_t light_paths = 0;  // traced from the lasers (render.light_paths), all sheets
  // Subsurface caches per laser sheet: 1 (the frame's), k > 1 (a moving
  // frame's time slices) or 0 (none: no subsurface laser light, or Monte Carlo).
  int entry_tree_slices = 0;
  double render_ms = 0;        // passes 1-3
  double ground_truth_ms = 0;  // stripe centres
  // Wall time of render_ms's parts, ms (the rest of render_ms: the printed
  // part's update and the lights): the chief rays and reach (pass 1), the
  // entry trees, the sample budgets and edges, the camera samples (pass 2),
  // the light paths, and the film's radiance and the sensor (pass 3).
  struct PassTimes {
    double chief_rays = 0, entry_trees = 0, budgets = 0, samples = 0, light_paths = 0, film_and_sensor = 0;
    // Calls f(name, ms) for each pass, by its manifest name.
    template <typename F>
    void ForEach(F&& f) const {
      f("chief_rays", chief_rays);
      f("entry_trees", entry_trees);
      f("budgets", budgets);
      f("samples", samples);
      f("light_paths", light_paths);
      f("film_and_sensor", film_and_sensor);
    }
    double Sum() const {
      double sum = 0;
      ForEach([&](const char*, double ms) { sum += ms; });
      return sum;
    }
  } pass_ms;
  // The printed part (scenes with "print"): chunks and triangles rebuilt for this
  // frame, and the part's triangles at the frame's time.
  uint64_t print_chunks_rebuilt = 0;
  uint64_t print_triangles_rebuilt = 0;
  uint64_t print_triangles = 0;
};

struct RenderedFrame {
  ShutterFrame shutter;
  Pose world_from_cam;                // at mid-exposure
  Image<uint16_t> raw;                // sensor output (DN), 1 channel (Bayer mosaic or mono)
  Image<float> radiance;              // 4 channels: R, G, B broadband and total laser, W/(m² sr), exposure-averaged
  Image<float> laser_radiance;        // 1 channel per laser sheet / pattern channel
  GroundTruthBuffers gt;
  Image<float> near_mask;             // 1 where the pixel got the full sample budget
  std::vector<StripeCenter> centers;  // exact stripe centres (laser lit frames)
  ScanAxis axis = ScanAxis::kRows;
  FrameStats stats;
};

class FrameRenderer {
 public:
  // Throws std::invalid_argument when the scene has a printed part (it needs the overload below).
  FrameRenderer(const SceneFile& scene, const EmbreeScene& embree, const RenderOverrides& overrides = {});
  // For any scene, including one with a printed part: `embree` must then be built
  // from mutable geometry (LoadSceneGeometry's, as shared_ptr<SceneGeometry>).
  FrameRenderer(const SceneFile& scene, EmbreeScene& embree, const RenderOverrides& overrides = {});
  ~FrameRenderer();

  int spp() const { return spp_; }
  uint64_t seed() const { return seed_; }
  RenderedFrame Render(int64_t frame_index) const;

 private:
  struct Impl;
  // What a pixel's chief hit may receive from the lasers directly: nothing, the
  // glow of their light below a subsurface surface (within the profile's reach
  // of a sheet), the beam (within 8 sigma, the pixel's footprint and the
  // profile's half-energy radius), or the sheet itself (within 3 sigma and the
  // pixel's footprint: where the laser lights the surface the pixel sees, and
  // its reflections start). kInSheet is also in the beam.
  enum Reach : uint8_t { kFar = 0, kInGlow = 1, kInBeam = 2, kInSheet = 3 };
  // Whether the scanner is at the same pose at t0 and t1 (no motion blur to sample).
  static bool IsStaticWithin(const Motion& motion, double t0, double t1);
  // Pass 1: ground truth, chief hits, and each pixel's Reach.
  void GroundTruthPass(const Pose& world_from_cam, const FrameLights& lights, RenderedFrame* out,
                       std::vector<ChiefHit>* hits, Image<uint8_t>* reach) const;
  // Each pixel's samples (render/frame_renderer_budgets.cpp): one, or the budget
  // with the first batch of a glow, or of a beam (pixels within one pixel and
  // the defocus blur of a kInBeam pixel; every pixel when `all_pixels`), or a
  // beam pixel at a geometric edge and near a kInSheet pixel, which takes
  // edge_spp_ (not when `all_pixels`). Sets RenderedFrame::near_mask to the
  // pixels with a budget.
  enum Budget : uint8_t { kOneSample = 0, kGlowBudget = 1, kBeamBudget = 2, kEdgeBudget = 3 };
  Image<uint8_t> SampleBudgets(const Image<uint8_t>& reach, std::span<const ChiefHit> hits, bool all_pixels,
                               RenderedFrame* out) const;
  // 1 where a pixel's chief hit and a neighbour's (4-neighbourhood) lie across a
  // geometric edge (see the header comment), else 0.
  Image<uint8_t> EdgePixels(std::span<const ChiefHit> hits, const Eigen::Vector3d& camera_origin) const;
  void SamplePass(const RenderedFrame& frame, const FrameLights& lights, const Image<uint8_t>& budget,
                  const SampleNoise& noise, Film* film, FrameStats* stats) const;
  // The frame's caches of laser light entering subsurface materials, one per
  // laser sheet (null where the grid would be too large), attached to `lights`.
  // `window_extra_m`: SheetWindowOfHits's extra_m.
  std::vector<std::unique_ptr<LaserEntryTree>> BuildEntryTrees(std::span<const ChiefHit> hits, FrameLights* lights,
                                                               FrameStats* stats, double window_extra_m = 0) const;
  // A moving frame's caches, one per laser sheet and time slice (`slices` equal
  // parts of the exposure, each cast at the pose of its middle), set in
  // lights->entry_tree_slices; none when together they would exceed
  // LaserEntryTree::kMaxPoints. reach_m: the farthest chief hit.
  std::vector<std::unique_ptr<LaserEntryTree>> BuildSlicedEntryTrees(std::span<const ChiefHit> hits,
                                                                     const ShutterFrame& sf, int slices, double reach_m,
                                                                     FrameLights* lights, FrameStats* stats) const;
  // The radiance images from the film (laser speckle applied, the laser total in
  // radiance channel 3) and the ground truth of the sheet that lights each pixel.
  // `splat`: the light paths' radiance per film laser channel, or empty.
  void RadianceFromFilm(const Film& film, const Image<float>& splat, const FrameLights& lights, int64_t frame_index,
                        RenderedFrame* out) const;
  // The sensor's input for a frame: energy per pixel over the exposure.
  SensorExposure ExposureOf(const RenderedFrame& frame) const;
  // The adaptive stop of a frame (render.adaptive_noise); sets the film's tracked value to electrons.
  SampleNoise MakeSampleNoise(const ShutterFrame& sf, FilmOptions* film_options) const;

  FrameRenderer(const SceneFile& scene, const EmbreeScene& embree, EmbreeScene* mutable_embree,
                const RenderOverrides& overrides);

  const SceneFile& scene_;
  const EmbreeScene& embree_;
  EmbreeScene* mutable_embree_ = nullptr;
  std::unique_ptr<PrintedPart> print_;  // state across frames (which chunks are built)
  int spp_;
  int edge_spp_;  // samples of a beam pixel at a geometric edge
  int threads_;
  uint64_t seed_;
  EmitterLayout layout_;
  Image<float> environment_map_;
  std::unique_ptr<PathTracer> tracer_;
  Image<float> radiance_to_irradiance_;  // Camera::RadianceToIrradiance per pixel
  double max_radiance_to_irradiance_ = 0;  // its largest value
  // Per material: the radius holding 99.9% of its widest subsurface profile (0 without one).
  std::vector<double> subsurface_reach_m_;
  // Per material: the radius holding half of that profile's energy (0 without one).
  std::vector<double> subsurface_half_m_;
  double min_subsurface_mfp_m_ = 0;  // smallest laser mean free path of a subsurface material (0: none)
  bool has_emission_ = false;
  double max_emission_ = 0;              // brightest emissive radiance, W/(m² sr)
  double max_environment_radiance_ = 0;  // brightest environment radiance, W/(m² sr)
};

}  // namespace lt

// The light transport of one camera sample: a path tracer over the Embree scene.
//
// Two kinds of light travel along each path. Broadband light (LED, environment,
// emissive surfaces) is carried in linear RGB. Monochromatic light (each laser
// projector, the pattern projector) is carried per emitter at its wavelength,
// with the material's reflectance at that wavelength (render/spectrum.h), and
// recorded per film channel (one per laser sheet), so the laser-only image and
// the sheet that lights each pixel come out of the same samples.
//
// At every path vertex:
//  - point emitters (delta lights) by next-event estimation: a shadow ray to the
//    projector and its analytic radiant intensity I(direction) / r²; points the
//    emitter cannot reach (LaserProjector::MayIlluminate) cost no ray;
//  - the LED rectangle by area sampling, combined with BSDF sampling by
//    multiple importance sampling (power heuristic); BSDF-sampled rays that meet
//    the rectangle add its radiance with the matching weight;
//  - the environment (constant or lat-long map) where a path escapes;
//  - subsurface materials: monochromatic light enters at nearby points x_i found
//    by probe rays (Burley's profile, axis MIS as in Christensen & Burley 2015)
//    and leaves at the shading point with the profile's weight R(|x_i − x_o|);
//    broadband light, which varies slowly across the profile's few hundred
//    micrometres, uses the local diffuse lobe (docs/rendering.md);
//  - at every vertex that may bounce, a connection through a point the laser
//    lights directly (a direction of the sheet drawn near the vertex, its first hit),
//    combined with the BSDF bounce by the balance heuristic: the stripe on the
//    print bed and its glint on a wall are thin lines a BSDF bounce rarely meets;
//    on a subsurface material it also takes the glow of the frame's cache there;
//  - the path continues by BSDF sampling up to max_bounces, with Russian
//    roulette from russian_roulette_depth.
//
// Laser light that a surface receives at grazing incidence and reflects on is
// the light paths' (TraceLightPaths, render/path_tracer_light_paths.cpp) in
// frames that trace them (FrameLights::grazing_by_light_paths): camera paths
// then leave out every path whose laser-lit vertex, reached after a bounce,
// meets the laser at a cosine below kGrazingCosine.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/image.h"
#include "core/pose.h"
#include "core/random.h"
#include "render/bsdf.h"
#include "render/frame_lights.h"
#include "render/subsurface_profile.h"
#include "scene/embree_scene.h"
#include "scene/material.h"
#include "scene/scene_settings.h"
#include "sensor/camera.h"
#include "sensor/rig.h"

namespace lt {

struct PathTracerOptions {
  int max_bounces = 2;
  int russian_roulette_depth = 3;
  bool subsurface = true;
  // Emitter rays per emitter channel for the subsurface light of the first
  // surface the camera sees (render/path_tracer_subsurface.cpp); one at bounces.
  int subsurface_emitter_rays = 8;
  // Path vertices connect to points the lasers light directly
  // (render/path_tracer_laser_connection.cpp).
  bool laser_connection = true;
};

// Counters of one thread's work.
struct TraceStats {
  uint64_t rays = 0;  // closest-hit and occlusion rays
};

// The exposure of a frame whose scanner moves, for the light paths: path i of n
// of a sheet takes the time t0 + (i + u) / n (t1 - t0), u uniform in [0, 1)
// (stratified over the exposure), and the camera's pose world_from_cam_at(t);
// the lasers move with the camera. displacement_m: how far a surface the camera
// sees moves relative to it from the middle of the exposure to its ends.
struct ExposureMotion {
  double t0 = 0, t1 = 0;
  std::function<Pose(double)> world_from_cam_at;
  double displacement_m = 0;
};

class PathTracer {
 public:
  static constexpr int kMaxGroups = kMaxRigEmitters;   // monochromatic emitters per rig
  static constexpr int kMaxChannels = kMaxRigSheets;   // film laser channels (sheets) per rig
  // The laser meets a surface at grazing incidence where the cosine of its
  // angle with the geometric normal is below this (60 degrees and more). Slot
  // walls across a 40 degree fan meet it at cosines up to 0.34; at 0.2, the
  // walls beyond 12 degrees stayed with camera paths and held the demo's
  // noisiest pixels (docs/performance.md).
  static constexpr double kGrazingCosine = 0.5;

  // `environment_map` is the lat-long map (3 channels) when the environment is a
  // map, else null. The scene, materials and map must outlive the tracer.
  PathTracer(const EmbreeScene& scene, const Environment& environment, const Image<float>* environment_map,
             const PathTracerOptions& options, int channels);

  // Adds the radiance arriving along `ray` (world frame, from the camera) to rgb
  // and mono (one entry per film channel), weighted by each light's lit fraction.
  // `laser_connection`: this sample may connect to laser-lit points (with
  // PathTracerOptions::laser_connection; the frame renderer spends it on the
  // pixels that get the sample budget).
  void Trace(const Ray& ray, const FrameLights& lights, Rng& rng, Eigen::Vector3f* rgb, std::span<float> mono,
             TraceStats* stats, bool laser_connection = true) const;

  // Light paths from every laser sheet through a reflection at grazing
  // incidence, connected to the camera at world_from_cam: adds their radiance
  // estimate (paths_per_sheet paths per sheet) to `splat` (the film's size, one
  // channel per film laser channel). With `motion` (a frame whose scanner moves)
  // each path takes its own time of the exposure, and the lasers (`lights`' at
  // that time's pose, ExposureMotion) and the camera posed then. The camera
  // paths of the frame must leave those paths out
  // (FrameLights::grazing_by_light_paths). The camera must not be a fisheye with
  // a thin lens. Deterministic for a seed and frame, at any thread count.
  void TraceLightPaths(const FrameLights& lights, const Camera& camera, const Pose& world_from_cam,
                       int64_t paths_per_sheet, uint64_t seed, int64_t frame, Image<float>* splat,
                       TraceStats* stats, const ExposureMotion* motion = nullptr) const;

  // Radiance of the environment in a world direction.
  Eigen::Vector3f EnvironmentRadiance(const Eigen::Vector3d& dir) const;
  bool has_environment() const { return has_environment_; }

  // Start of a secondary ray leaving surface point p (world) with geometric
  // normal n toward `dir`: offset along ±n by an amount that clears Embree's float
  // error in the render frame.
  Eigen::Vector3d SpawnOrigin(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& dir) const;

 private:
  struct Vertex;
  // Whether a material scatters light below its surface in this render.
  bool ScattersBelowSurface(const Material& m) const { return options_.subsurface && m.subsurface.has_value(); }
  // The BSDF with which a surface reflects an emitter's light directly (next-event
  // estimation and the laser-lit connection): the material's at the emitter's
  // wavelength, or only its specular lobe when subsurface light replaces the diffuse one.
  static BsdfParams EmitterReflection(const Material& m, bool subsurface, float albedo_at_wavelength);
  // Directions of one laser sheet drawn toward a path vertex x0 for the
  // connection through laser-lit points (render/path_tracer_laser_connection.cpp):
  // fan angle phi from a Cauchy density centred on x0's (spread: x0's angle out
  // of the sheet, at least 1 mrad), truncated to the fan; psi across the sheet
  // from a Gaussian. Projector frame.
  struct SheetConnection {
    const LaserProjector* laser = nullptr;
    int sheet = 0;
    double phi0 = 0, spread = 0, a1 = 0, a2 = 0, sigma = 0;
    bool Make(const PointEmitter& e, int sheet_index, const Eigen::Vector3d& x0);
    double Pdf(const Eigen::Vector3d& w) const;  // per steradian, w unit
    bool Sample(Rng& rng, Eigen::Vector3d* w) const;
  };
  // The fan angles a sheet's light paths are drawn from: a grid of kFanCells
  // cells over the fan; `grazing` (sorted) lists the cells whose ends meet a
  // surface at grazing incidence, or a crease, a jump or a miss between them;
  // sigma: the Gaussian across the sheet.
  struct FanCells {
    double half_width = 0, step = 0, sigma = 0;
    double r_near = 0;  // distance of the nearest surface the grid meets
    std::vector<int> grazing;
    double PhiDensity(double phi) const;  // per radian
    double SamplePhi(Rng& rng) const;
  };
  FanCells FindGrazingCells(const PointEmitter& e, int sheet, TraceStats* stats) const;
  // Solid-angle density at x0 of reaching the lit point x1 by the connection
  // (cos_1l: x1's normal to the laser, cos_1: to x0).
  double LaserConnectionDensity(const PointEmitter& e, int sheet, const Eigen::Vector3d& x0,
                                const Eigen::Vector3d& x1, double cos_1l, double cos_1) const;
  void ConnectToLaserLight(const Vertex& v, const FrameLights& lights, std::span<const float> beta_mono, Rng& rng,
                           std::span<float> mono, TraceStats* stats) const;
  // after_bounce: v was reached by a bounce (not seen by the camera). prev_p:
  // the previous path vertex when it connected to laser-lit points (balance
  // heuristic against that connection, with prev_bsdf_pdf), else null.
  void AddEmitterLight(const Vertex& v, const FrameLights& lights, std::span<const float> beta_mono,
                       bool after_bounce, const Eigen::Vector3d* prev_p, float prev_bsdf_pdf,
                       std::span<float> mono, TraceStats* stats) const;
  void AddLedLight(const Vertex& v, const LedLight& led, const Eigen::Vector3f& beta, Rng& rng,
                   Eigen::Vector3f* rgb, TraceStats* stats) const;
  // How light below a subsurface material leaves it: the material's profile at
  // the laser's mean free path, its reach, and the exit factor toward a
  // direction at cos_o to the shading normal (render/path_tracer_subsurface.cpp).
  struct SubsurfaceExit {
    double albedo;
    BurleyProfile profile;
    double r_max = 0, exit = 0;
    SubsurfaceExit(const Material& m, float albedo_at_wavelength, const GgxAlpha& ggx, float cos_o);
  };
  // Sheet k's cache of entry points when it covers the profile's reach about x, else null.
  static const LaserEntryTree* CoveringTree(const PointEmitter& e, int k, const Eigen::Vector3d& x, double r_max);
  // Subsurface light of one emitter (render/path_tracer_subsurface.cpp). prev_p:
  // the previous path vertex when it connected to laser-lit points (the cached
  // glow is then weighed against the connection's, with prev_bsdf_pdf), else null.
  void AddSubsurfaceEmitter(const Vertex& v, const FrameLights& lights, const PointEmitter& e, float beta,
                            int emitter_rays, const Eigen::Vector3d* prev_p, float prev_bsdf_pdf, Rng& rng,
                            std::span<float> mono, TraceStats* stats) const;
  // Solid-angle density at x0 with which the connection reaches x1 (geometric
  // normal n1 facing x0) and takes the glow of its cache there: zero unless the
  // laser lights x1 directly (MayIlluminate, unshadowed: one shadow ray) from the
  // side that faces x0 and the light paths do not own x1.
  double GlowConnectionDensity(const PointEmitter& e, int sheet, const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                               const Eigen::Vector3d& n1, bool grazing_by_light_paths, TraceStats* stats) const;
  // Irradiance factor I_k cos/r² at p for each channel of emitter e (written to
  // per_channel), or false when p is unlit (shadowed, outside the beam, facing away).
  bool EmitterIrradiance(const PointEmitter& e, const Eigen::Vector3d& p, const Eigen::Vector3d& n_geo,
                         const Eigen::Vector3d& n_shade, Eigen::Vector3d* wi, double* cos_shade,
                         std::span<double> per_channel, TraceStats* stats) const;

  const EmbreeScene& scene_;
  const std::vector<Material>& materials_;
  std::vector<GgxAlpha> material_ggx_;  // per material
  const Environment& environment_;
  const Image<float>* environment_map_;
  PathTracerOptions options_;
  int channels_;
  bool has_environment_;
};

}  // namespace lt

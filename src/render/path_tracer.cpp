#include "render/path_tracer.h"
#include "render/path_vertex.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "render/bsdf.h"
#include "render/sampling.h"
#include "render/spectrum.h"
#include "render/subsurface_profile.h"

namespace lt {

namespace {

constexpr int kMaxGroups = PathTracer::kMaxGroups;
constexpr int kMaxChannels = PathTracer::kMaxChannels;

Eigen::Vector3f F(const Eigen::Vector3d& v) { return v.cast<float>(); }
Eigen::Vector3d D(const Eigen::Vector3f& v) { return v.cast<double>(); }

// Ray meets the LED rectangle (one-sided, emitting along its +z) before t_max.
std::optional<double> IntersectLed(const LedLight& led, const Eigen::Vector3d& o, const Eigen::Vector3d& dir,
                                   double t_max) {
  const Pose& world_from_led = led.world_from_led;
  Eigen::Vector3d n = world_from_led.linear().col(2);
  double denom = n.dot(dir);
  if (denom >= 0) return std::nullopt;  // arriving from behind (or parallel)
  double t = n.dot(world_from_led.translation() - o) / denom;
  if (!(t > 0 && t < t_max)) return std::nullopt;
  Eigen::Vector3d q = world_from_led.inverse() * (o + t * dir);
  const auto& p = led.led->params();
  if (std::abs(q.x()) > 0.5 * p.width_m || std::abs(q.y()) > 0.5 * p.height_m) return std::nullopt;
  return t;
}

// Solid-angle density of sampling direction `dir` from `o` by LED area sampling.
double LedPdfSolidAngle(const LedLight& led, const Eigen::Vector3d& dir_unit, double dist) {
  const Pose& world_from_led = led.world_from_led;
  double cos_l = -world_from_led.linear().col(2).dot(dir_unit);
  if (cos_l <= 0) return 0;
  return dist * dist / (cos_l * led.led->area_m2());
}

Eigen::Vector3f LedRadiance(const LedLight& led, const Eigen::Vector3d& dir_from_led_world) {
  Eigen::Vector3d dir_in_cam = led.world_from_cam.linear().transpose() * dir_from_led_world;
  auto L = led.led->Radiance(dir_in_cam);
  return Eigen::Vector3f(float(L[0]), float(L[1]), float(L[2])) * float(led.weight);
}

}  // namespace


PathTracer::PathTracer(const EmbreeScene& scene, const Environment& environment,
                       const Image<float>* environment_map, const PathTracerOptions& options, int channels)
    : scene_(scene),
      materials_(scene.geometry().materials),
      environment_(environment),
      environment_map_(environment_map),
      options_(options),
      channels_(channels) {
  for (const Material& m : materials_) material_ggx_.emplace_back(m.roughness);
  if (channels > kMaxChannels) {
    throw std::invalid_argument("at most " + std::to_string(kMaxChannels) + " laser sheets are supported");
  }
  has_environment_ = environment.kind == Environment::Kind::kMap
                         ? (environment_map != nullptr && environment.scale > 0)
                         : environment.radiance.maxCoeff() > 0;
}

Eigen::Vector3f PathTracer::EnvironmentRadiance(const Eigen::Vector3d& dir) const {
  if (!has_environment_) return Eigen::Vector3f::Zero();
  if (environment_.kind == Environment::Kind::kConstant) return F(environment_.radiance);
  // Lat-long map, world z up: u = azimuth from -x (u = 0) through -y, +x (u = 0.5), +y; v = polar angle from +z.
  Eigen::Vector3d d = dir.normalized();
  double u = (std::atan2(d.y(), d.x()) + M_PI) / (2 * M_PI);
  double v = std::acos(std::clamp(d.z(), -1.0, 1.0)) / M_PI;
  const Image<float>& m = *environment_map_;
  int x = std::clamp(int(u * m.width), 0, m.width - 1);
  int y = std::clamp(int(v * m.height), 0, m.height - 1);
  int c = m.channels;
  Eigen::Vector3f L(m.At(x, y, 0), m.At(x, y, std::min(1, c - 1)), m.At(x, y, std::min(2, c - 1)));
  return L * float(environment_.scale);
}

Eigen::Vector3d PathTracer::SpawnOrigin(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                                        const Eigen::Vector3d& dir) const {
  double magnitude = std::max(scene_.RenderFromWorld(p).cwiseAbs().maxCoeff(), 1e-4);
  double eps = 1e-5 * magnitude;
  return p + (n.dot(dir) >= 0 ? eps : -eps) * n;
}

bool PathTracer::EmitterIrradiance(const PointEmitter& e, const Eigen::Vector3d& p, const Eigen::Vector3d& n_geo,
                                   const Eigen::Vector3d& n_shade, Eigen::Vector3d* wi, double* cos_shade,
                                   std::span<double> per_channel, TraceStats* stats) const {
  Eigen::Vector3d p_proj = e.projector_from_world * p;
  if (e.laser && !e.laser->MayIlluminate(p_proj)) return false;
  Eigen::Vector3d to = e.origin_world - p;
  double r2 = to.squaredNorm();
  if (!(r2 > 0)) return false;
  double r = std::sqrt(r2);
  *wi = to / r;
  if (n_geo.dot(*wi) <= 0) return false;
  *cos_shade = n_shade.dot(*wi);
  if (*cos_shade <= 0) return false;
  double total = 0;
  if (e.laser) {
    if (e.channels == 1) {
      per_channel[0] = e.laser->SheetIntensityAt(0, p_proj);
    } else {
      for (int k = 0; k < e.channels; ++k) per_channel[size_t(k)] = e.laser->SheetIntensityAt(k, p_proj);
    }
  } else {
    per_channel[0] = e.pattern->RadiantIntensityAt(p_proj);
  }
  for (int k = 0; k < e.channels; ++k) total += per_channel[size_t(k)];
  if (!(total > 0)) return false;
  Ray shadow;
  shadow.origin = SpawnOrigin(p, n_geo, *wi);
  shadow.direction = e.origin_world - shadow.origin;
  shadow.t_min = 0;
  shadow.t_max = 1.0 - 1e-7;
  ++stats->rays;
  if (scene_.Occluded(shadow)) return false;
  for (int k = 0; k < e.channels; ++k) per_channel[size_t(k)] *= e.weight / r2;
  return true;
}

BsdfParams PathTracer::EmitterReflection(const Material& m, bool subsurface, float albedo_at_wavelength) {
  return {Eigen::Vector3f::Constant(subsurface ? 0.0f : albedo_at_wavelength), subsurface ? 0.0f : m.metallic,
          m.roughness};
}

void PathTracer::AddEmitterLight(const Vertex& v, const FrameLights& lights, std::span<const float> beta_mono,
                                 bool after_bounce, const Eigen::Vector3d* prev_p, float prev_bsdf_pdf,
                                 std::span<float> mono, TraceStats* stats) const {
  std::array<double, kMaxChannels> irr{};
  for (const PointEmitter& e : lights.emitters) {
    float beta = beta_mono[size_t(e.group)];
    if (beta <= 0) continue;
    if (after_bounce && e.laser && lights.grazing_by_light_paths &&
        std::abs(v.n_geo.dot((e.origin_world - v.p).normalized())) < kGrazingCosine) {
      continue;  // the light paths' part
    }
    Eigen::Vector3d wi;
    double cos_s = 0;
    std::span<double> ch(irr.data(), size_t(e.channels));
    if (!EmitterIrradiance(e, v.p, v.n_geo, v.n_shade, &wi, &cos_s, ch, stats)) continue;
    const BsdfParams params = EmitterReflection(*v.material, v.subsurface, v.albedo_mono[size_t(e.group)]);
    float f = Bsdf(params.base_color, params.metallic, v.ggx).Evaluate(v.wo, v.ToLocal(wi)).x();
    if (f <= 0) continue;
    double scale = double(beta) * f * cos_s;
    const bool connected = prev_p && e.laser;
    const double cos_1 = connected ? v.n_geo.dot((*prev_p - v.p).normalized()) : 0.0;
    for (int k = 0; k < e.channels; ++k) {
      double weight = 1.0;
      if (connected) {
        const double p_connect = LaserConnectionDensity(e, k, *prev_p, v.p, v.n_geo.dot(wi), cos_1);
        if (prev_bsdf_pdf + p_connect > 0) weight = prev_bsdf_pdf / (prev_bsdf_pdf + p_connect);
      }
      mono[size_t(e.first_channel + k)] += float(scale * weight * ch[size_t(k)]);
    }
  }
}

void PathTracer::AddLedLight(const Vertex& v, const LedLight& led, const Eigen::Vector3f& beta, Rng& rng,
                             Eigen::Vector3f* rgb, TraceStats* stats) const {
  Eigen::Vector2d u(rng.NextDouble(), rng.NextDouble());
  LedSample s = led.led->Sample(u);
  Eigen::Vector3d p_led = led.world_from_cam * s.p_in_cam;
  Eigen::Vector3d to = p_led - v.p;
  double dist = to.norm();
  if (!(dist > 0)) return;
  Eigen::Vector3d wi = to / dist;
  if (v.n_geo.dot(wi) <= 0) return;
  double pdf_light = LedPdfSolidAngle(led, wi, dist);
  if (!(pdf_light > 0)) return;
  Eigen::Vector3f L = LedRadiance(led, -wi);
  if (L.maxCoeff() <= 0) return;
  Bsdf bsdf(v.base_color, v.material->metallic, v.ggx);
  Eigen::Vector3f wi_local = v.ToLocal(wi);
  Eigen::Vector3f f = bsdf.Evaluate(v.wo, wi_local);
  float cos_s = wi_local.z();
  if (cos_s <= 0 || f.maxCoeff() <= 0) return;
  Ray shadow;
  shadow.origin = SpawnOrigin(v.p, v.n_geo, wi);
  shadow.direction = p_led - shadow.origin;
  shadow.t_min = 0;
  shadow.t_max = 1.0 - 1e-7;
  ++stats->rays;
  if (scene_.Occluded(shadow)) return;
  float w = PowerHeuristic(1, float(pdf_light), 1, bsdf.Pdf(v.wo, wi_local));
  *rgb += beta.cwiseProduct(f).cwiseProduct(L) * (cos_s * w / float(pdf_light));
}

void PathTracer::Trace(const Ray& camera_ray, const FrameLights& lights, Rng& rng, Eigen::Vector3f* rgb,
                       std::span<float> mono, TraceStats* stats, bool laser_connection) const {
  const bool connection = options_.laser_connection && laser_connection;
  Eigen::Vector3f beta = Eigen::Vector3f::Ones();
  std::array<float, kMaxGroups> beta_mono;
  beta_mono.fill(1.0f);
  std::span<const float> beta_mono_span(beta_mono.data(), size_t(std::max(lights.groups, 0)));
  std::array<double, kMaxGroups> group_wavelength{};
  for (const auto& e : lights.emitters) group_wavelength[size_t(e.group)] = e.wavelength_m;

  Ray ray = camera_ray;
  float prev_bsdf_pdf = 0;  // for MIS when a BSDF-sampled ray meets the LED or a laser-lit point
  Eigen::Vector3d prev_p = Eigen::Vector3d::Zero();
  for (int depth = 0;; ++depth) {
    ++stats->rays;
    auto hit = scene_.Intersect(ray);
    Eigen::Vector3d dir = ray.direction.normalized();
    if (depth > 0 && lights.led) {
      double t_scene = hit ? hit->t * ray.direction.norm() : std::numeric_limits<double>::infinity();
      Ray unit{ray.origin, dir, 0, t_scene};
      if (auto t_led = IntersectLed(*lights.led, unit.origin, dir, t_scene)) {
        double pdf_light = LedPdfSolidAngle(*lights.led, dir, *t_led);
        float w = PowerHeuristic(1, prev_bsdf_pdf, 1, float(pdf_light));
        *rgb += beta.cwiseProduct(LedRadiance(*lights.led, -dir)) * w;
      }
    }
    if (!hit) {
      *rgb += beta.cwiseProduct(EnvironmentRadiance(dir));
      return;
    }
    Vertex v;
    v.material_id = hit->material_id;
    v.material = &materials_[hit->material_id];
    v.p = hit->position;
    v.n_geo = hit->geometric_normal;
    if (v.n_geo.dot(dir) > 0) v.n_geo = -v.n_geo;  // face the arriving path (both sides shade)
    v.n_shade = hit->shading_normal;
    if (v.n_shade.dot(v.n_geo) < 0) v.n_shade = -v.n_shade;
    v.frame = Frame::FromNormal(F(v.n_shade));
    v.wo = v.ToLocal(-dir);
    if (v.wo.z() <= 0) v.wo.z() = 1e-6f;  // shading normal bent away from the viewer
    v.wo.normalize();
    v.base_color = BaseColorAt(*v.material, *hit);
    v.ggx = material_ggx_[hit->material_id];
    for (int g = 0; g < lights.groups && g < kMaxGroups; ++g) {
      v.albedo_mono[size_t(g)] = ValueAtWavelength(v.base_color, group_wavelength[size_t(g)]);
    }
    v.subsurface = ScattersBelowSurface(*v.material);

    if (v.material->emissive.maxCoeff() > 0) *rgb += beta.cwiseProduct(v.material->emissive);
    if (!lights.emitters.empty()) {
      // Every vertex that may bounce also connects to laser-lit points (see
      // ConnectToLaserLight); the vertex after it weighs its next-event
      // estimate against that connection.
      const bool connects = connection && depth < options_.max_bounces;
      const bool connected = connection && depth > 0;
      AddEmitterLight(v, lights, beta_mono_span, depth > 0, connected ? &prev_p : nullptr, prev_bsdf_pdf, mono,
                      stats);
      if (connects) ConnectToLaserLight(v, lights, beta_mono_span, rng, mono, stats);
      if (v.subsurface) {
        const int emitter_rays = depth == 0 ? options_.subsurface_emitter_rays : 1;
        for (const PointEmitter& e : lights.emitters)
          AddSubsurfaceEmitter(v, lights, e, beta_mono[size_t(e.group)], emitter_rays,
                               connected ? &prev_p : nullptr, prev_bsdf_pdf, rng, mono, stats);
      }
    }
    if (lights.led) AddLedLight(v, *lights.led, beta, rng, rgb, stats);

    if (depth >= options_.max_bounces) return;
    Bsdf bsdf(v.base_color, v.material->metallic, v.ggx);
    float u1 = rng.NextFloat(), u2 = rng.NextFloat(), u3 = rng.NextFloat();
    BsdfSample bs = bsdf.Sample(v.wo, u1, u2, u3);
    if (!bs.valid()) return;
    Eigen::Vector3d wi = D(v.frame.ToWorld(bs.wi)).normalized();
    if (wi.dot(v.n_geo) <= 0) return;  // below the geometric surface: would leak
    beta = beta.cwiseProduct(bs.weight);
    float cos_i = bs.wi.z();
    for (int g = 0; g < lights.groups && g < kMaxGroups; ++g) {
      if (beta_mono[size_t(g)] <= 0) continue;
      float a = v.albedo_mono[size_t(g)];
      float f = Bsdf(Eigen::Vector3f::Constant(a), v.material->metallic, v.ggx).Evaluate(v.wo, bs.wi).x();
      beta_mono[size_t(g)] *= f * cos_i / bs.pdf;
    }
    prev_bsdf_pdf = bs.pdf;
    prev_p = v.p;
    if (depth + 1 >= options_.russian_roulette_depth) {
      float m = beta.maxCoeff();
      for (int g = 0; g < lights.groups && g < kMaxGroups; ++g) m = std::max(m, beta_mono[size_t(g)]);
      float q = std::min(1.0f, m);
      if (rng.NextFloat() >= q) return;
      beta /= q;
      for (auto& b : beta_mono) b /= q;
    }
    ray.origin = SpawnOrigin(v.p, v.n_geo, wi);
    ray.direction = wi;
    ray.t_min = 0;
    ray.t_max = std::numeric_limits<double>::infinity();
  }
}

}  // namespace lt

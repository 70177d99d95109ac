// Subsurface light from the scanner's point emitters (see path_tracer.h).
//
// Light leaving the shading point x_o of a subsurface material is
//   L_o = C_o * integral over the surface of R(|x_i - x_o|) (1 - E(cos_i)) E_i(x_i) dA_i,
//   C_o = (1 - E(cos_o)) / (pi (1 - E_avg)),
// with R Burley's normalized diffusion profile at the emitter's wavelength, E the
// dielectric specular albedo (the same coupling as the BSDF's diffuse lobe, so a
// vanishing mean free path gives back the diffuse lobe) and E_i the emitter's
// irradiance at the entry point x_i. The profile is truncated at the radius
// r_max holding 99.9% of its energy.
//
// In a frame where the scanner holds still during the exposure (or moves by
// less than a quarter of the cache's entry spacing, FrameRenderer::Render: the
// mid-exposure pose's cache), each laser sheet's lit entry points are cast once
// per frame and summed by a tree (render/laser_entry_tree.h,
// render.subsurface_cache): a channel whose cache covers the profile's reach
// around x_o takes that sum, without noise. Other channels (a faster scanner,
// the pattern projector, points outside the cache's window) use Monte Carlo:
//
// Two strategies find entry points, combined by the balance heuristic
// (Veach 1997) over one probe sample and M emitter samples per channel
// (weight f / (p_probe + M p_emitter) for every sample):
//  - probe rays around x_o (Christensen & Burley 2015; King et al. 2013): a
//    radius from the profile, an angle, and an axis (normal 1/2, tangents 1/4
//    each), then a ray through the disc point along the axis; every hit on the
//    same material is an entry point, with the axis-MIS area density;
//  - emitter rays: the laser's light is confined to thin sheets, which probe
//    rays rarely meet, so entry points are also drawn along the sheet from the
//    projector, over the fan angles within r_max of x_o (with a density that
//    follows the profile's 1/d fall-off, see EmitterWindow) and across the
//    sheet from its Gaussian (a cone of directions for a pattern projector);
//    the first surface hit is the lit entry point. The M draws are stratified
//    along the sheet (the profile varies most there); M is larger at the
//    camera vertex (PathTracerOptions::subsurface_emitter_rays), where the
//    glow is seen directly, than at bounces.
#include <cmath>

#include "render/path_tracer.h"
#include "render/laser_entry_tree.h"
#include "render/path_vertex.h"
#include "render/specular_albedo.h"
#include "render/subsurface_profile.h"

namespace lt {

namespace {

constexpr int kMaxProbeHits = 8;
constexpr double kProfileTruncation = 0.999;

// The emitter-ray strategy for one channel: a window of directions around x_o.
struct EmitterWindow {
  bool sheet = true;
  // Sheet: the laser and its sheet k (angles phi, psi: LaserProjector::Angles), the
  // fan angle of x_o, the window half-width and the sampling sigma across.
  const LaserProjector* laser = nullptr;
  int k = 0;
  double phi0 = 0, dphi = 0, sigma = 0;
  // Across the sheet, psi (the angle out of the sheet's plane) is drawn from
  // the sheet's Gaussian; psi0 is the angle of x_o. Then along the sheet, the
  // offset delta = phi - phi0 has density 1 / (2 V sqrt(delta^2 + dh^2)) on
  // |delta| < dphi, V = asinh(dphi / dh), dh = max(|psi - psi0|, dh_min): it
  // follows the profile's 1/d fall-off along the line of entry points at that
  // psi, seen from x_o (delta = dh sinh(v), v uniform on (-V, V)). Matching the
  // 1/d singularity for each line leaves only a logarithmic one in the weight
  // where the stripe passes through x_o, where the peak of the glow is.
  double psi0 = 0, dh_min = 1e-6;
  double Dh(double psi) const { return std::max(std::abs(psi - psi0), dh_min); }
  // Pattern: a cone around the direction of x_o.
  Eigen::Vector3d axis;
  double cos_max = 1;

  // Density (per steradian, projector frame) of drawing unit direction w.
  double Pdf(const Eigen::Vector3d& w) const {
    if (!sheet) return w.dot(axis) >= cos_max ? 1.0 / (2 * M_PI * (1 - cos_max)) : 0.0;
    const LaserProjector::SheetAngles a = laser->Angles(k, w);
    const double psi = a.psi;
    double dp = std::remainder(a.phi - phi0, 2 * M_PI);
    if (std::abs(dp) > dphi || std::abs(psi) >= 0.5 * M_PI) return 0.0;
    double g = std::exp(-0.5 * psi * psi / (sigma * sigma)) / (sigma * std::sqrt(2 * M_PI));
    double dh = Dh(psi), V = std::asinh(dphi / dh);
    double p_delta = 1.0 / (2 * V * std::sqrt(dp * dp + dh * dh));
    return p_delta * g / std::cos(psi);
  }
  // Draws a unit direction (projector frame); false when the draw falls outside.
  bool Sample(Rng& rng, double u_along, Eigen::Vector3d* w) const {
    if (!sheet) {
      double cos_t = 1 - rng.NextDouble() * (1 - cos_max), sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
      double a = 2 * M_PI * rng.NextDouble();
      Eigen::Vector3d t = axis.unitOrthogonal(), b = axis.cross(t);
      *w = cos_t * axis + sin_t * (std::cos(a) * t + std::sin(a) * b);
      return true;
    }
    double psi = sigma * rng.NextGaussian();
    if (std::abs(psi) >= 0.5 * M_PI) return false;
    double dh = Dh(psi), V = std::asinh(dphi / dh);
    double phi = phi0 + dh * std::sinh((2 * u_along - 1) * V);
    *w = laser->DirectionAt(k, phi, psi);
    return true;
  }
};

}  // namespace

PathTracer::SubsurfaceExit::SubsurfaceExit(const Material& m, float albedo_at_wavelength, const GgxAlpha& ggx,
                                           float cos_o)
    : albedo((1.0 - m.metallic) * albedo_at_wavelength),
      profile([&] {
        DiffusionProfileParams pp;
        pp.albedo = std::max(albedo, 1e-6);
        pp.mean_free_path = m.subsurface->mean_free_path_laser_m;
        return pp;
      }()) {
  static const double truncation_log_root = BurleyProfile::LogRoot(kProfileTruncation);
  r_max = profile.RadiusOfLogRoot(truncation_log_root);  // = SampleRadius(kProfileTruncation)
  cos_o = std::clamp(cos_o, 0.0f, 1.0f);
  exit = (1.0 - DielectricSpecularAlbedo(cos_o, ggx.row)) / (M_PI * (1.0 - DielectricSpecularAlbedoAverage(ggx.row)));
}

const LaserEntryTree* PathTracer::CoveringTree(const PointEmitter& e, int k, const Eigen::Vector3d& x,
                                               double r_max) {
  const LaserEntryTree* tree = size_t(k) < e.entry_trees.size() ? e.entry_trees[size_t(k)] : nullptr;
  return tree && tree->Covers(x, r_max) ? tree : nullptr;
}

void PathTracer::AddSubsurfaceEmitter(const Vertex& v, const FrameLights& lights, const PointEmitter& e, float beta,
                                      int emitter_rays, const Eigen::Vector3d* prev_p, float prev_bsdf_pdf, Rng& rng,
                                      std::span<float> mono, TraceStats* stats) const {
  const SubsurfaceExit out(*v.material, v.albedo_mono[size_t(e.group)], v.ggx, v.wo.z());
  const double albedo = out.albedo;
  if (beta <= 0 || albedo <= 0) return;
  const BurleyProfile& profile = out.profile;
  const double r_max = out.r_max;
  const double scale = double(beta) * out.exit;
  // Channels whose frame cache covers the profile's reach around x_o: no noise.
  // After a bounce from a vertex that connected to laser-lit points, the cache's
  // glow is weighed against the connection's (ConnectToLaserLight), which
  // reaches x_o when the laser lights it directly.
  std::array<bool, kMaxChannels> cached{};
  bool all_cached = true;
  for (int k = 0; k < e.channels; ++k) {
    if (const LaserEntryTree* tree = CoveringTree(e, k, v.p, r_max)) {
      double weight = 1.0;
      if (prev_p && e.laser) {
        const double p_connect =
            GlowConnectionDensity(e, k, *prev_p, v.p, v.n_geo, lights.grazing_by_light_paths, stats);
        if (prev_bsdf_pdf + p_connect > 0) weight = prev_bsdf_pdf / (prev_bsdf_pdf + p_connect);
      }
      mono[size_t(e.first_channel + k)] +=
          float(scale * weight * tree->Sum(v.p, v.n_geo, v.material_id, profile, r_max));
      cached[size_t(k)] = true;
    } else {
      all_cached = false;
    }
  }
  if (all_cached) return;
  const Frame axes = Frame::FromNormal(v.n_geo.cast<float>());
  const std::array<Eigen::Vector3d, 3> axis = {axes.n.cast<double>(), axes.t.cast<double>(), axes.b.cast<double>()};
  const std::array<double, 3> axis_prob = {0.5, 0.25, 0.25};

  // Area density of reaching x (normal n) by a probe ray.
  auto probe_pdf = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& n) {
    Eigen::Vector3d d = x - v.p;
    double pdf = 0;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d in_plane = d - d.dot(axis[size_t(k)]) * axis[size_t(k)];
      double rk = in_plane.norm();
      if (rk >= r_max) continue;
      pdf += axis_prob[size_t(k)] * profile.Evaluate(rk) / (albedo * kProfileTruncation) *
             std::abs(n.dot(axis[size_t(k)]));
    }
    return pdf;
  };
  // Entry-point weight without the emitter: R(d) (1 - E(cos_i)), 0 beyond r_max.
  auto entry = [&](const Eigen::Vector3d& x, double cos_i) {
    double d = (x - v.p).norm();
    if (d >= r_max || cos_i <= 0) return 0.0;
    return profile.Evaluate(d) * (1.0 - DielectricSpecularAlbedo(float(std::min(cos_i, 1.0)), v.ggx.row));
  };

  // Windows of the emitter-ray strategy, one per channel.
  const Eigen::Vector3d p_proj = e.projector_from_world * v.p;
  const double dist = p_proj.norm();
  if (!(dist > 0)) return;
  std::array<EmitterWindow, kMaxChannels> windows;
  std::array<bool, kMaxChannels> active{};
  for (int k = 0; k < e.channels; ++k) {
    if (cached[size_t(k)]) continue;
    EmitterWindow& w = windows[size_t(k)];
    if (e.laser) {
      w.laser = e.laser;
      w.k = k;
      const LaserProjector::SheetAngles a = e.laser->Angles(k, p_proj / dist);
      w.phi0 = a.phi;
      w.dphi = std::min(M_PI, r_max / dist);
      w.sigma = e.laser->SheetSigma(dist);
      w.psi0 = a.psi;
      w.dh_min = 1e-6 * w.dphi;
      active[size_t(k)] = std::abs(w.psi0) <= w.dphi + 8 * w.sigma;  // the sheet passes within reach
    } else {
      w.sheet = false;
      w.axis = p_proj / dist;
      w.cos_max = std::cos(std::min(0.5 * M_PI, std::atan(r_max / dist)));
      active[size_t(k)] = true;
    }
  }
  bool any = false;
  for (int k = 0; k < e.channels; ++k) any = any || active[size_t(k)];
  if (!any) return;
  const Eigen::Matrix3d world_from_projector = e.projector_from_world.linear().transpose();
  // Emitter-ray density of x as an area density: p_w * cos_i / r^2.
  auto emitter_pdf = [&](int k, const Eigen::Vector3d& x, const Eigen::Vector3d& n) {
    if (!active[size_t(k)]) return 0.0;
    Eigen::Vector3d to = e.origin_world - x;
    double r2 = to.squaredNorm(), cos_i = n.dot(to) / std::sqrt(r2);
    if (cos_i <= 0) return 0.0;
    Eigen::Vector3d w_proj = (e.projector_from_world * x).normalized();
    return windows[size_t(k)].Pdf(w_proj) * cos_i / r2;
  };

  // Strategy 1: a probe ray.
  {
    double r = profile.SampleRadius(kProfileTruncation * rng.NextDouble());
    double phi = 2 * M_PI * rng.NextDouble();
    float ua = rng.NextFloat();
    int a = ua < 0.5f ? 0 : (ua < 0.75f ? 1 : 2);
    const Eigen::Vector3d &w = axis[size_t(a)], &s = axis[size_t((a + 1) % 3)], &t = axis[size_t((a + 2) % 3)];
    double h = std::sqrt(std::max(0.0, r_max * r_max - r * r));
    Ray probe{v.p + r * (std::cos(phi) * s + std::sin(phi) * t) + h * w, -w, 0, 2 * h};
    std::array<double, kMaxChannels> irr{};
    for (int found = 0; found < kMaxProbeHits && probe.t_min < probe.t_max; ++found) {
      ++stats->rays;
      auto hit = scene_.Intersect(probe);
      if (!hit) break;
      probe.t_min = hit->t + 1e-6 * std::max(h, 1e-9);
      if (hit->material_id != v.material_id) continue;
      Eigen::Vector3d ni = hit->geometric_normal;
      if (ni.dot(v.n_geo) < 0) ni = -ni;
      Eigen::Vector3d wi;
      double cos_i = 0;
      std::span<double> ch(irr.data(), size_t(e.channels));
      if (!EmitterIrradiance(e, hit->position, ni, ni, &wi, &cos_i, ch, stats)) continue;
      double g = entry(hit->position, cos_i);
      double pp = probe_pdf(hit->position, ni);
      if (g <= 0 || !(pp > 0)) continue;
      for (int k = 0; k < e.channels; ++k) {
        if (cached[size_t(k)]) continue;
        double f = g * ch[size_t(k)] * cos_i;  // ch: I_k / r^2 times the lit fraction
        mono[size_t(e.first_channel + k)] += float(scale * f / (pp + emitter_rays * emitter_pdf(k, hit->position, ni)));
      }
    }
  }
  // Strategy 2: M emitter rays per channel within reach, stratified along the sheet.
  for (int k = 0; k < e.channels; ++k) {
    if (!active[size_t(k)]) continue;
    const double u0 = rng.NextDouble();
    for (int m = 0; m < emitter_rays; ++m) {
      Eigen::Vector3d w_proj;
      if (!windows[size_t(k)].Sample(rng, (m + u0) / emitter_rays, &w_proj)) continue;
      Ray ray{e.origin_world, world_from_projector * w_proj, 0, std::numeric_limits<double>::infinity()};
      ++stats->rays;
      auto hit = scene_.Intersect(ray);
      if (!hit || hit->material_id != v.material_id) continue;
      Eigen::Vector3d ni = hit->geometric_normal;
      if (ni.dot(v.n_geo) < 0) ni = -ni;
      Eigen::Vector3d to = e.origin_world - hit->position;
      double r2 = to.squaredNorm(), cos_i = ni.dot(to) / std::sqrt(r2);
      double g = entry(hit->position, cos_i);
      if (g <= 0) continue;
      Eigen::Vector3d p_hit_proj = e.projector_from_world * hit->position;
      double I = e.laser ? e.laser->SheetIntensityAt(k, p_hit_proj) : e.pattern->RadiantIntensityAt(p_hit_proj);
      double f = g * I * e.weight * cos_i / r2;
      double pl = emitter_pdf(k, hit->position, ni);
      if (!(pl > 0)) continue;
      mono[size_t(e.first_channel + k)] += float(scale * f / (probe_pdf(hit->position, ni) + emitter_rays * pl));
    }
  }
}

}  // namespace lt

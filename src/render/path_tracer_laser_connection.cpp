// Laser light reflected once by another surface toward a path vertex: a
// connection through the laser-lit point (see path_tracer.h).
//
// The laser lights thin lines: the stripe on the print bed, its glint on a
// wall. A bounce drawn from the BSDF at x0 meets them only by chance. So each
// path vertex x0 that may bounce (PathTracerOptions::laser_connection) also
// draws a direction w of the sheet from the projector, near the fan angle
// of x0 (density in w known in closed form, SheetConnection), casts it to its
// first hit x1, the lit point, and connects x1 to x0 with a shadow ray. The
// light x1 sends to x0 is f1 I(w) cos_s1 / r1^2 (the same reflection of the
// laser as next-event estimation computes at x1: the surface's BSDF, and for a
// subsurface material its specular lobe only). x1's area density is
// p(w) cos_1L / r1^2, so in solid angle at x0 p_c = p(w) cos_1L d^2 / (r1^2 cos_1),
// and the connection and the BSDF bounce combine by the balance heuristic:
//   connection: f0 L1 cos0 / (p_c + p_bsdf);
//   next-event estimation at the BSDF-sampled vertex after x0: weight p_bsdf / (p_bsdf + p_c).
// On a subsurface material that the frame's cache covers, where the laser lights
// x1 within MayIlluminate, the connection also takes the glow leaving x1 toward
// x0 (the cache's sum, as a vertex at x1 would): the glow is brightest on the lit
// line. The glow a BSDF bounce finds at x1 is then weighed by
// p_bsdf / (p_bsdf + p_c(x1)), p_c from GlowConnectionDensity (zero where the
// laser does not reach x1 directly: one shadow ray). The glow beside the lit
// line stays with the BSDF bounce.
#include <cmath>

#include "render/bsdf.h"
#include "render/laser_entry_tree.h"
#include "render/path_tracer.h"
#include "render/path_vertex.h"
#include "render/spectrum.h"

namespace lt {

namespace {

// Spread of the fan-angle density at its centre, radians (about 0.1 mm at 0.1 m).
constexpr double kMinFanSpread = 1e-3;
// Across the sheet, psi is drawn from a Gaussian this much wider than the
// sheet's at x0's distance, so that hits farther away (a wider sheet) keep a
// bounded weight.
constexpr double kAcrossWidening = 1.5;

}  // namespace

bool PathTracer::SheetConnection::Make(const PointEmitter& e, int sheet_index, const Eigen::Vector3d& x0) {
  if (!e.laser) return false;
  const Eigen::Vector3d p = e.projector_from_world * x0;
  const double r0 = p.norm();
  if (!(r0 > 0)) return false;
  laser = e.laser;
  sheet = sheet_index;
  const LaserProjector::SheetAngles a = laser->Angles(sheet, p / r0);
  phi0 = a.phi;
  spread = std::max(std::abs(a.psi), kMinFanSpread);
  const double limit = laser->FanHalfWidth();
  a1 = std::atan((-limit - phi0) / spread);
  a2 = std::atan((limit - phi0) / spread);
  sigma = kAcrossWidening * laser->SheetSigma(r0);
  return a2 > a1;
}

double PathTracer::SheetConnection::Pdf(const Eigen::Vector3d& w) const {
  const LaserProjector::SheetAngles s = laser->Angles(sheet, w);
  const double a = std::atan((s.phi - phi0) / spread);
  if (!(a >= a1 && a <= a2) || std::abs(s.psi) >= 0.5 * M_PI) return 0.0;
  const double dp = s.phi - phi0;
  const double p_phi = spread / ((a2 - a1) * (spread * spread + dp * dp));
  const double p_psi = std::exp(-0.5 * s.psi * s.psi / (sigma * sigma)) / (sigma * std::sqrt(2 * M_PI));
  return p_phi * p_psi / std::cos(s.psi);
}

bool PathTracer::SheetConnection::Sample(Rng& rng, Eigen::Vector3d* w) const {
  const double phi = phi0 + spread * std::tan(a1 + rng.NextDouble() * (a2 - a1));
  const double psi = sigma * rng.NextGaussian();
  if (std::abs(psi) >= 0.5 * M_PI) return false;
  *w = laser->DirectionAt(sheet, phi, psi);
  return true;
}

double PathTracer::LaserConnectionDensity(const PointEmitter& e, int sheet, const Eigen::Vector3d& x0,
                                          const Eigen::Vector3d& x1, double cos_1l, double cos_1) const {
  SheetConnection sc;
  if (!sc.Make(e, sheet, x0) || !(cos_1 > 0)) return 0.0;
  const Eigen::Vector3d q = e.projector_from_world * x1;
  const double r2 = q.squaredNorm();
  return sc.Pdf(q / std::sqrt(r2)) * cos_1l / r2 * (x1 - x0).squaredNorm() / cos_1;
}

double PathTracer::GlowConnectionDensity(const PointEmitter& e, int sheet, const Eigen::Vector3d& x0,
                                         const Eigen::Vector3d& x1, const Eigen::Vector3d& n1,
                                         bool grazing_by_light_paths, TraceStats* stats) const {
  if (!e.laser->MayIlluminate(e.projector_from_world * x1)) return 0.0;
  const Eigen::Vector3d to_laser = e.origin_world - x1;
  const double r_l = to_laser.norm();
  const double cos_1l = n1.dot(to_laser) / r_l;
  if (!(cos_1l > 0)) return 0.0;
  if (grazing_by_light_paths && cos_1l < kGrazingCosine) return 0.0;
  const double cos_1 = n1.dot((x0 - x1).normalized());
  const double density = LaserConnectionDensity(e, sheet, x0, x1, cos_1l, cos_1);
  if (!(density > 0)) return 0.0;
  // The connection reaches x1 only as the first hit from the projector.
  Ray shadow;
  shadow.origin = SpawnOrigin(x1, n1, to_laser);
  shadow.direction = e.origin_world - shadow.origin;
  shadow.t_min = 0;
  shadow.t_max = 1.0 - 1e-7;
  ++stats->rays;
  return scene_.Occluded(shadow) ? 0.0 : density;
}

void PathTracer::ConnectToLaserLight(const Vertex& v, const FrameLights& lights, std::span<const float> beta_mono,
                                     Rng& rng, std::span<float> mono, TraceStats* stats) const {
  for (const PointEmitter& e : lights.emitters) {
    const float beta = beta_mono[size_t(e.group)];
    if (!e.laser || beta <= 0) continue;
    const Eigen::Matrix3d world_from_projector = e.projector_from_world.linear().transpose();
    for (int k = 0; k < e.channels; ++k) {
      SheetConnection sc;
      Eigen::Vector3d w;
      if (!sc.Make(e, k, v.p) || !sc.Sample(rng, &w)) continue;
      Ray ray{e.origin_world, world_from_projector * w, 0, std::numeric_limits<double>::infinity()};
      ++stats->rays;
      const auto hit = scene_.Intersect(ray);
      if (!hit) continue;
      const Eigen::Vector3d x1 = hit->position;
      const Eigen::Vector3d to_laser = e.origin_world - x1;
      const double r_l2 = to_laser.squaredNorm();
      const Eigen::Vector3d wl = to_laser / std::sqrt(r_l2);
      Eigen::Vector3d n1 = hit->geometric_normal;
      if (n1.dot(wl) < 0) n1 = -n1;  // the lit side
      const Eigen::Vector3d to0 = v.p - x1;
      const double d2 = to0.squaredNorm();
      if (!(d2 > 0)) continue;
      const Eigen::Vector3d w1 = to0 / std::sqrt(d2);  // x1 -> x0
      const double cos_1l = n1.dot(wl), cos_1 = n1.dot(w1);
      if (!(cos_1l > 0) || !(cos_1 > 0)) continue;
      if (lights.grazing_by_light_paths && cos_1l < kGrazingCosine) continue;  // the light paths' part
      const Eigen::Vector3f wi0 = v.ToLocal(-w1);
      const float cos0 = wi0.z();
      if (v.n_geo.dot(-w1) <= 0 || cos0 <= 0) continue;
      // The reflection at x1, as next-event estimation computes it there, and
      // the glow of the sheet's cache leaving x1 toward x0, as a vertex at x1
      // would take it (where the laser lights x1 within MayIlluminate).
      const Material& m1 = materials_[hit->material_id];
      Eigen::Vector3d ns1 = hit->shading_normal;
      if (ns1.dot(n1) < 0) ns1 = -ns1;
      const Frame frame1 = Frame::FromNormal(ns1.cast<float>());
      Eigen::Vector3f wo1 = frame1.ToLocal(w1.cast<float>());
      if (wo1.z() <= 0) wo1.z() = 1e-6f;
      wo1.normalize();
      const Eigen::Vector3f wl1 = frame1.ToLocal(wl.cast<float>());
      const float a1 = float(ValueAtWavelength(BaseColorAt(m1, *hit), e.wavelength_m));
      const Eigen::Vector3d p1_proj = e.projector_from_world * x1;
      double l1 = 0;
      if (wl1.z() > 0) {
        const float f1 = Bsdf(EmitterReflection(m1, ScattersBelowSurface(m1), a1)).Evaluate(wo1, wl1).x();
        l1 = std::max(0.0, f1 * e.laser->SheetIntensityAt(k, p1_proj) * e.weight * wl1.z() / r_l2);
      }
      if (ScattersBelowSurface(m1) && e.laser->MayIlluminate(p1_proj)) {
        const SubsurfaceExit out(m1, a1, material_ggx_[hit->material_id], wo1.z());
        if (const LaserEntryTree* tree = out.albedo > 0 ? CoveringTree(e, k, x1, out.r_max) : nullptr)
          l1 += out.exit * tree->Sum(x1, n1, hit->material_id, out.profile, out.r_max);
      }
      if (!(l1 > 0)) continue;
      const float f0 =
          Bsdf(Eigen::Vector3f::Constant(v.albedo_mono[size_t(e.group)]), v.material->metallic, v.ggx)
              .Evaluate(v.wo, wi0)
              .x();
      if (f0 <= 0) continue;
      Ray shadow;
      shadow.origin = SpawnOrigin(v.p, v.n_geo, -w1);
      shadow.direction = SpawnOrigin(x1, n1, w1) - shadow.origin;
      shadow.t_min = 0;
      shadow.t_max = 1.0 - 1e-7;
      ++stats->rays;
      if (scene_.Occluded(shadow)) continue;
      const double p_connect = sc.Pdf(w) * cos_1l / r_l2 * d2 / cos_1;
      const double p_bsdf = Bsdf(v.base_color, v.material->metallic, v.ggx).Pdf(v.wo, wi0);
      if (!(p_connect + p_bsdf > 0)) continue;
      mono[size_t(e.first_channel + k)] += float(double(beta) * f0 * cos0 * l1 / (p_connect + p_bsdf));
    }
  }
}

}  // namespace lt

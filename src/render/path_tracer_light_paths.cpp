// Laser light reflected at grazing incidence, traced from the lasers and
// splatted to the camera (see path_tracer.h).
//
// Where a laser sheet meets a surface almost edge-on (a slot wall under a sheet
// that crosses the slot), the wall takes a sliver of the fan and reflects it,
// mostly by Fresnel reflection, onto the floor within micrometres of the
// corner. A camera path finds that light only by chance: the sheet connection
// draws the wall's points with an area density proportional to the grazing
// cosine, and a BSDF bounce has to meet the reflection's narrow lobe. Such rare
// bright paths made most of the dim frame's stripe noise (docs/performance.md).
// From the laser the same paths are easy: a direction of the sheet that meets
// the wall, a reflection drawn from the wall's BSDF, and a connection of every
// later vertex to the camera.
//
// The two kinds of path share the work by a partition of path space, not by
// weights: a path whose laser-lit vertex x1 is reached after at least one bounce
// and has cos_1L = |n_1 . w_L| < kGrazingCosine (geometric normal, laser
// direction) belongs to the light paths; camera paths skip it (next-event
// estimation at a bounce vertex and the sheet connection, path_tracer.cpp and
// path_tracer_laser_connection.cpp). Each estimator is unbiased on its part.
//
// One light path of sheet k: a fan angle phi from a mixture (kUniformShare
// uniform over the fan, the rest uniform over the cells of a grid of the fan
// where the sheet meets a surface at grazing incidence or jumps between
// surfaces, FindGrazingCells) and psi across the sheet from a Gaussian wider
// than the sheet's; density p_w = p_phi p_psi / cos psi per steradian. Its
// first hit x1 carries, against the camera paths' integrand in area measure,
//   T1 = I(w) / p_w * (cos_s1L / cos_1L) * f1(w_1 -> x2, w_L) cos_1(w_1) / p_1(w_1),
// the reflection at x1 being the one next-event estimation computes there
// (PathTracer::EmitterReflection). At each later vertex x_j (j <= max_bounces + 1)
// the path connects to a point l of the lens (the pinhole, or uniform on the
// aperture as the camera draws it) and adds to the pixel u that sees x_j through l
//   T_j * f_j(w_cam, w_in) * cos_sj(w_in) / cos_j(w_in) * |du / dA_j|,
//   |du / dA_j| = cos_j(l) / d_l^2 * (d_lf^2 / cos_lf) * (cos_cf / d_cf^2) / PixelSolidAngle(u),
// where f is the point's BSDF at the wavelength, P_f the point on the focus plane
// that x_j's ray through l crosses (at distances d_lf from l and d_cf from the
// lens centre, at angles lf, cf to the axis); for a pinhole the two middle
// factors cancel. Then the path bounces by the BSDF, T_{j+1} = T_j f_j cos_j(out)
// / p_j * cos_sj(in) / cos_j(in). The image of those splats, divided by the
// number of paths, is added to the film's mean.
//
// In a frame whose scanner moves, path i of n takes the time
// t = t0 + (i + u) / n (t1 - t0) of the exposure (u from its own random stream,
// so that a still frame's paths are unchanged), the lasers and the camera at
// their poses then, and splats into the pixel the camera sees then: the mean
// over the exposure that the camera's moving samples also take.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "render/bsdf.h"
#include "render/path_tracer.h"
#include "render/sampling.h"
#include "render/spectrum.h"

namespace lt {

namespace {

constexpr uint64_t kLightPathPurpose = 0x4c49474854504154ull;
constexpr uint64_t kLightPathTimePurpose = 0x4c5041544854494dull;  // a path's time in a moving frame
// A moving frame's light paths find their grazing cells at the poses of the
// middles of equal parts of the exposure, as many as keep the scanner's travel
// over each within one cell at the nearest surface, at most this many; a path
// takes the cells of the part holding its time (any cells are a valid
// proposal: the uniform share covers the whole fan).
constexpr int kTimeSlices = 16;
// Cells of the grid over the fan that locates grazing hits and jumps.
constexpr int kFanCells = 4096;
// Share of light paths drawn uniformly over the whole fan (so that every grazing
// point the grid misses keeps a density).
constexpr double kUniformShare = 0.25;
// psi is drawn from a Gaussian this much wider than the widest sheet sigma at
// the grid's distances, so that I(w) / p_w stays bounded.
constexpr double kAcrossWidening = 1.5;
// Light paths per task.
constexpr int64_t kChunk = 512;

struct Splat {
  uint32_t pixel;
  uint16_t channel;
  float value;
};

}  // namespace

PathTracer::FanCells PathTracer::FindGrazingCells(const PointEmitter& e, int sheet, TraceStats* stats) const {
  const LaserProjector& laser = *e.laser;
  FanCells cells;
  cells.half_width = laser.FanHalfWidth();
  cells.step = 2 * cells.half_width / kFanCells;
  const Eigen::Matrix3d world_from_projector = e.projector_from_world.linear().transpose();
  struct GridHit {
    bool valid = false;
    Eigen::Vector3d p, n;
    double r = 0, cos_l = 0;
  };
  std::vector<GridHit> grid(size_t(kFanCells) + 1);
  tbb::parallel_for(0, kFanCells + 1, [&](int i) {
    const double phi = -cells.half_width + i * cells.step;
    Ray ray{e.origin_world, world_from_projector * laser.DirectionAt(sheet, phi, 0.0), 0,
            std::numeric_limits<double>::infinity()};
    const auto hit = scene_.Intersect(ray);
    if (!hit) return;
    GridHit& g = grid[size_t(i)];
    g.valid = true;
    g.p = hit->position;
    g.r = (g.p - e.origin_world).norm();
    const Eigen::Vector3d wl = (e.origin_world - g.p) / g.r;
    g.n = hit->geometric_normal;
    if (g.n.dot(wl) < 0) g.n = -g.n;
    g.cos_l = g.n.dot(wl);
  });
  stats->rays += uint64_t(kFanCells) + 1;
  static const double kCosCrease = std::cos(30.0 * M_PI / 180.0);
  double sigma = 0;
  for (int i = 0; i < kFanCells; ++i) {
    const GridHit &a = grid[size_t(i)], &b = grid[size_t(i) + 1];
    if (a.valid) sigma = std::max(sigma, laser.SheetSigma(a.r));
    bool flag = a.valid != b.valid;
    if (a.valid && b.valid) {
      // On one surface met at a cosine of at least kGrazingCosine, neighbouring
      // hits lie at most r step / kGrazingCosine apart.
      const double jump = (a.p - b.p).norm() * kGrazingCosine / (std::max(a.r, b.r) * cells.step);
      flag = a.cos_l < kGrazingCosine || b.cos_l < kGrazingCosine || a.n.dot(b.n) < kCosCrease || jump > 1.5;
    }
    if (flag) cells.grazing.push_back(i);
  }
  if (grid.back().valid) sigma = std::max(sigma, laser.SheetSigma(grid.back().r));
  cells.sigma = kAcrossWidening * sigma;
  cells.r_near = INFINITY;
  for (const GridHit& g : grid) cells.r_near = g.valid ? std::min(cells.r_near, g.r) : cells.r_near;
  return cells;
}

double PathTracer::FanCells::PhiDensity(double phi) const {
  if (std::abs(phi) > half_width) return 0.0;
  double p = (grazing.empty() ? 1.0 : kUniformShare) / (2 * half_width);
  if (!grazing.empty()) {
    const int cell = std::min(int((phi + half_width) / step), kFanCells - 1);
    if (std::binary_search(grazing.begin(), grazing.end(), cell))
      p += (1 - kUniformShare) / (double(grazing.size()) * step);
  }
  return p;
}

double PathTracer::FanCells::SamplePhi(Rng& rng) const {
  const double u = rng.NextDouble();
  if (grazing.empty() || u < kUniformShare) return -half_width + 2 * half_width * rng.NextDouble();
  const size_t cell = std::min(size_t(rng.NextDouble() * double(grazing.size())), grazing.size() - 1);
  return -half_width + (grazing[cell] + rng.NextDouble()) * step;
}

void PathTracer::TraceLightPaths(const FrameLights& lights, const Camera& camera, const Pose& world_from_cam,
                                 int64_t paths_per_sheet, uint64_t seed, int64_t frame, Image<float>* splat,
                                 TraceStats* stats, const ExposureMotion* motion) const {
  const Pose cam_from_world_mid = world_from_cam.inverse();
  const bool pinhole = camera.is_pinhole();
  const double lens_radius = pinhole ? 0.0 : 0.5 * camera.aperture_diameter_m();
  const double focus = camera.focus_distance_m();
  for (const PointEmitter& e : lights.emitters) {
    if (!e.laser || !(e.weight > 0)) continue;
    for (int k = 0; k < e.channels; ++k) {
      // The grazing cells: of the frame's pose, or of each time slice's.
      std::vector<FanCells> slice_cells{FindGrazingCells(e, k, stats)};
      const double travel_cells =
          motion ? 2 * motion->displacement_m / (slice_cells[0].step * slice_cells[0].r_near) : 0.0;
      if (travel_cells > 1) {
        const int slices = int(std::min(std::ceil(travel_cells), double(kTimeSlices)));
        slice_cells.clear();
        for (int s = 0; s < slices; ++s) {
          const double t_s = motion->t0 + (motion->t1 - motion->t0) * (s + 0.5) / slices;
          slice_cells.push_back(FindGrazingCells(EmitterAt(e, motion->world_from_cam_at(t_s)), k, stats));
        }
      }
      double sigma = 0;
      for (const FanCells& c : slice_cells) sigma = std::max(sigma, c.sigma);
      if (!(sigma > 0)) continue;
      for (FanCells& c : slice_cells) c.sigma = c.sigma > 0 ? c.sigma : sigma;  // a slice whose fan hits nothing
      const int channel = e.first_channel + k;
      const int64_t chunks = (paths_per_sheet + kChunk - 1) / kChunk;
      std::vector<std::vector<Splat>> chunk_splats(static_cast<size_t>(chunks));
      tbb::enumerable_thread_specific<TraceStats> tstats;
      tbb::parallel_for(int64_t(0), chunks, [&](int64_t c) {
        TraceStats& ts = tstats.local();
        std::vector<Splat>& out = chunk_splats[size_t(c)];
        for (int64_t i = c * kChunk; i < std::min(paths_per_sheet, (c + 1) * kChunk); ++i) {
          Rng rng = Rng::For(seed, uint64_t(frame), uint64_t(channel), uint64_t(i), kLightPathPurpose);
          // The path's poses: the frame's, or at its time of a moving exposure.
          const FanCells* cells_at = &slice_cells[0];
          Pose world_from_cam_path = world_from_cam, cam_from_world_path = cam_from_world_mid;
          ProjectorPlacement projector{e.projector_from_world, e.origin_world};
          if (motion) {
            Rng time_rng = Rng::For(seed, uint64_t(frame), uint64_t(channel), uint64_t(i), kLightPathTimePurpose);
            const double u = (double(i) + time_rng.NextDouble()) / double(paths_per_sheet);
            cells_at = &slice_cells[std::min(size_t(u * double(slice_cells.size())), slice_cells.size() - 1)];
            world_from_cam_path = motion->world_from_cam_at(motion->t0 + u * (motion->t1 - motion->t0));
            cam_from_world_path = world_from_cam_path.inverse();
            projector = PlaceProjector(e, world_from_cam_path);
          }
          const Eigen::Matrix3d world_from_projector = projector.projector_from_world.linear().transpose();
          const Eigen::Vector3d& origin = projector.origin_world;
          const FanCells& cells = *cells_at;
          const double phi = cells.SamplePhi(rng);
          const double psi = cells.sigma * rng.NextGaussian();
          if (std::abs(psi) >= 0.5 * M_PI) continue;
          const double p_w = cells.PhiDensity(phi) *
                             std::exp(-0.5 * psi * psi / (cells.sigma * cells.sigma)) /
                             (cells.sigma * std::sqrt(2 * M_PI)) / std::cos(psi);
          if (!(p_w > 0)) continue;
          Ray ray{origin, world_from_projector * e.laser->DirectionAt(k, phi, psi), 0,
                  std::numeric_limits<double>::infinity()};
          ++ts.rays;
          const auto hit1 = scene_.Intersect(ray);
          if (!hit1) continue;
          // The laser-lit vertex: only grazing ones are the light paths' part.
          const Eigen::Vector3d x1 = hit1->position;
          const Eigen::Vector3d to_laser = origin - x1;
          const double r_l = to_laser.norm();
          const Eigen::Vector3d wl = to_laser / r_l;
          Eigen::Vector3d n1 = hit1->geometric_normal;
          if (n1.dot(wl) < 0) n1 = -n1;
          const double cos_1l = n1.dot(wl);
          if (!(cos_1l > 0 && cos_1l < kGrazingCosine)) continue;
          const Eigen::Vector3d p_proj = projector.projector_from_world * x1;
          if (!e.laser->MayIlluminate(p_proj)) continue;
          const double intensity = e.laser->SheetIntensityAt(k, p_proj) * e.weight;
          if (!(intensity > 0)) continue;
          const Material& m1 = materials_[hit1->material_id];
          Eigen::Vector3d ns1 = hit1->shading_normal;
          if (ns1.dot(n1) < 0) ns1 = -ns1;
          const Frame frame1 = Frame::FromNormal(ns1.cast<float>());
          const Eigen::Vector3f wl1 = frame1.ToLocal(wl.cast<float>());
          if (wl1.z() <= 0) continue;
          const float a1 = float(ValueAtWavelength(BaseColorAt(m1, *hit1), e.wavelength_m));
          const BsdfParams params = EmitterReflection(m1, ScattersBelowSurface(m1), a1);
          const Bsdf bsdf1(params.base_color, params.metallic, material_ggx_[hit1->material_id]);
          const BsdfSample bs1 = bsdf1.Sample(wl1, rng.NextFloat(), rng.NextFloat(), rng.NextFloat());
          if (!bs1.valid()) continue;
          Eigen::Vector3d w = frame1.ToWorld(bs1.wi).cast<double>().normalized();
          const double cos_1 = n1.dot(w);
          if (!(cos_1 > 0)) continue;
          const float f1 = bsdf1.Evaluate(bs1.wi, wl1).x();
          double throughput = intensity / p_w * (wl1.z() / cos_1l) * f1 * cos_1 / bs1.pdf;
          Eigen::Vector3d x_prev = x1, n_prev = n1;
          for (int bounce = 1; bounce <= options_.max_bounces && throughput > 0; ++bounce) {
            Ray next{SpawnOrigin(x_prev, n_prev, w), w, 0, std::numeric_limits<double>::infinity()};
            ++ts.rays;
            const auto hit = scene_.Intersect(next);
            if (!hit) break;
            const Eigen::Vector3d x = hit->position;
            Eigen::Vector3d n = hit->geometric_normal;
            if (n.dot(w) > 0) n = -n;  // toward where the light came from
            const double cos_in = -n.dot(w);
            const Material& m = materials_[hit->material_id];
            Eigen::Vector3d ns = hit->shading_normal;
            if (ns.dot(n) < 0) ns = -ns;
            const Frame frame_x = Frame::FromNormal(ns.cast<float>());
            const Eigen::Vector3f w_in = frame_x.ToLocal((-w).cast<float>());
            if (!(cos_in > 0) || w_in.z() <= 0) break;
            const float a = float(ValueAtWavelength(BaseColorAt(m, *hit), e.wavelength_m));
            const Bsdf bsdf(Eigen::Vector3f::Constant(a), m.metallic, material_ggx_[hit->material_id]);
            const double shading = double(w_in.z()) / cos_in;
            // Connect x to a point of the lens.
            Eigen::Vector3d lens = Eigen::Vector3d::Zero();
            if (!pinhole) {
              const Eigen::Vector2d d = ConcentricDisk(Eigen::Vector2d(rng.NextDouble(), rng.NextDouble()));
              lens = Eigen::Vector3d(d.x() * lens_radius, d.y() * lens_radius, 0.0);
            }
            const Eigen::Vector3d x_cam = cam_from_world_path * x;
            if (x_cam.z() > 0) {
              const Eigen::Vector3d p_f = pinhole ? x_cam : Eigen::Vector3d(lens + (x_cam - lens) * (focus / x_cam.z()));
              const auto u = camera.Project(p_f);
              const Eigen::Vector3d lens_world = world_from_cam_path * lens;
              const Eigen::Vector3d to_lens = lens_world - x;
              const double d_l = to_lens.norm();
              const Eigen::Vector3d wc = to_lens / d_l;
              const double cos_c = n.dot(wc);
              if (u && camera.InImage(*u) && cos_c > 0) {
                Eigen::Vector3f wo = frame_x.ToLocal(wc.cast<float>());
                if (wo.z() <= 0) wo.z() = 1e-6f;  // as the camera path clamps it
                wo.normalize();
                const float f = bsdf.Evaluate(wo, w_in).x();
                if (f > 0) {
                  Ray shadow;
                  shadow.origin = SpawnOrigin(x, n, wc);
                  shadow.direction = lens_world - shadow.origin;
                  shadow.t_min = 0;
                  shadow.t_max = 1.0 - 1e-7;
                  ++ts.rays;
                  if (!scene_.Occluded(shadow)) {
                    const Eigen::Vector3d lf = p_f - lens;
                    const double d_lf = lf.norm(), d_cf = p_f.norm();
                    const double focus_factor = (d_lf * d_lf / (lf.z() / d_lf)) * ((p_f.z() / d_cf) / (d_cf * d_cf));
                    const double jacobian = cos_c / (d_l * d_l) * focus_factor / camera.PixelSolidAngle(*u);
                    const int px = std::clamp(int(std::floor(u->x() + 0.5)), 0, camera.width() - 1);
                    const int py = std::clamp(int(std::floor(u->y() + 0.5)), 0, camera.height() - 1);
                    const double value = throughput * f * shading * jacobian;
                    if (value > 0 && std::isfinite(value))
                      out.push_back({uint32_t(py) * uint32_t(camera.width()) + uint32_t(px), uint16_t(channel),
                                     float(value)});
                  }
                }
              }
            }
            if (bounce == options_.max_bounces) break;
            // Bounce on (the camera path's BSDF at x, drawn from the light's side).
            const BsdfSample bs = bsdf.Sample(w_in, rng.NextFloat(), rng.NextFloat(), rng.NextFloat());
            if (!bs.valid()) break;
            const Eigen::Vector3d w_out = frame_x.ToWorld(bs.wi).cast<double>().normalized();
            const double cos_out = n.dot(w_out);
            if (!(cos_out > 0)) break;
            const float f = bsdf.Evaluate(bs.wi, w_in).x();
            throughput *= f * cos_out / bs.pdf * shading;
            x_prev = x, n_prev = n, w = w_out;
          }
        }
      });
      for (const TraceStats& t : tstats) stats->rays += t.rays;
      const double scale = 1.0 / double(paths_per_sheet);
      for (const auto& chunk : chunk_splats)
        for (const Splat& s : chunk) splat->pixels[size_t(s.pixel) * size_t(splat->channels) + s.channel] += float(s.value * scale);
    }
  }
}

}  // namespace lt

// Which pixels get the sample budget, and with what first batch
// (FrameRenderer::SampleBudgets), and which of the beam's pixels lie at a
// geometric edge (FrameRenderer::EdgePixels).
#include <tbb/parallel_for.h>

#include <cmath>

#include "render/frame_renderer.h"

namespace lt {

namespace {

// Surfaces that meet at more than this angle make an edge (a printed bead's
// curvature turns its normal by less between neighbouring pixels at the
// scanner's resolutions).
constexpr double kCreaseDegrees = 30.0;
// Beam pixels within this many pixels of an edge take the edge budget: a grazing
// wall between two faces can span two pixels.
constexpr int kEdgeDilation = 2;

// Whether chief hits a and b (their normals oriented toward the camera) lie
// across an edge: a crease, or one off the other's plane by more than the
// pixel's footprint there (a step between faces of equal normals).
bool AcrossEdge(const ChiefHit& a, const Eigen::Vector3d& na, const ChiefHit& b, const Eigen::Vector3d& nb,
                double footprint_per_m) {
  static const double kCosCrease = std::cos(kCreaseDegrees * M_PI / 180.0);
  if (a.valid != b.valid) return true;
  if (!a.valid) return false;
  if (na.dot(nb) < kCosCrease) return true;
  const Eigen::Vector3d d = b.p_world - a.p_world;
  return std::abs(na.dot(d)) > a.depth * footprint_per_m || std::abs(nb.dot(d)) > b.depth * footprint_per_m;
}

// 1 where a pixel within `radius` (a square, Chebyshev distance) satisfies
// `in`, else 0: separably, along the rows, then along the columns of that.
template <typename In>
Image<uint8_t> Dilate(int w, int h, int radius, In&& in) {
  Image<uint8_t> along_rows(w, h, 1, 0), out(w, h, 1, 0);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x)
      for (int xx = std::max(0, x - radius); xx <= std::min(w - 1, x + radius); ++xx)
        if (in(xx, y)) {
          along_rows.At(x, y) = 1;
          break;
        }
  });
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x)
      for (int yy = std::max(0, y - radius); yy <= std::min(h - 1, y + radius); ++yy)
        if (along_rows.At(x, yy)) {
          out.At(x, y) = 1;
          break;
        }
  });
  return out;
}

}  // namespace

Image<uint8_t> FrameRenderer::EdgePixels(std::span<const ChiefHit> hits, const Eigen::Vector3d& camera_origin) const {
  const Camera& cam = scene_.sensor.camera;
  const int w = cam.width(), h = cam.height();
  const double footprint_per_m = cam.pixel_pitch_m() / cam.image_distance_m();
  auto hit = [&](int x, int y) -> const ChiefHit& { return hits[size_t(y) * size_t(w) + size_t(x)]; };
  // Normals facing the camera, so that the two sides of a thin surface agree.
  std::vector<Eigen::Vector3d> normal(hits.size(), Eigen::Vector3d::Zero());
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const ChiefHit& c = hit(x, y);
      Eigen::Vector3d& n = normal[size_t(y) * size_t(w) + size_t(x)];
      n = c.normal;
      if (c.valid && n.dot(camera_origin - c.p_world) < 0) n = -n;
    }
  });
  auto n_at = [&](int x, int y) -> const Eigen::Vector3d& { return normal[size_t(y) * size_t(w) + size_t(x)]; };
  Image<uint8_t> edge(w, h, 1, 0);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
        if (AcrossEdge(hit(x, y), n_at(x, y), hit(nx[k], ny[k]), n_at(nx[k], ny[k]), footprint_per_m)) {
          edge.At(x, y) = 1;
          break;
        }
      }
    }
  });
  return edge;
}

Image<uint8_t> FrameRenderer::SampleBudgets(const Image<uint8_t>& reach, std::span<const ChiefHit> hits,
                                            bool all_pixels, RenderedFrame* out) const {
  const Camera& cam = scene_.sensor.camera;
  const int w = cam.width(), h = cam.height();
  Image<uint8_t> budget(w, h, 1, all_pixels ? kBeamBudget : kOneSample);
  if (!all_pixels) {
    // The beam's pixels dilated by one pixel plus the largest defocus blur radius
    // seen in the frame; the rest of the glow's pixels.
    double max_coc = 0;
    if (!cam.is_pinhole()) {
      for (float z : out->gt.depth.pixels)
        if (z > 0) max_coc = std::max(max_coc, cam.CircleOfConfusionPx(z));
    }
    const int radius = 1 + int(std::ceil(0.5 * max_coc));
    // A square dilation of the beam's pixels; the rest of the glow's pixels.
    const Image<uint8_t> beam = Dilate(w, h, radius, [&](int x, int y) { return reach.At(x, y) >= kInBeam; });
    tbb::parallel_for(0, h, [&](int y) {
      for (int x = 0; x < w; ++x)
        budget.At(x, y) = beam.At(x, y) ? kBeamBudget : reach.At(x, y) == kInGlow ? kGlowBudget : kOneSample;
    });
    if (edge_spp_ > spp_) {
      // Beam pixels within kEdgeDilation of an edge pixel and within
      // kEdgeDilation plus the beam's radius of the sheet itself: where the
      // stripe crosses an edge and the laser's reflection off one face lands on
      // the other. The beam's wider part (the glow's half-energy radius), seen
      // across a printed part's bead valleys, would be edge pixels nearly all.
      const Image<uint8_t> edge = EdgePixels(hits, out->world_from_cam.translation());
      const Image<uint8_t> near_edge = Dilate(w, h, kEdgeDilation, [&](int x, int y) { return edge.At(x, y) != 0; });
      const Image<uint8_t> near_sheet =
          Dilate(w, h, radius + kEdgeDilation, [&](int x, int y) { return reach.At(x, y) == kInSheet; });
      tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x)
          if (budget.At(x, y) == kBeamBudget && near_edge.At(x, y) && near_sheet.At(x, y)) budget.At(x, y) = kEdgeBudget;
      });
    }
  }
  out->near_mask = Image<float>(w, h, 1, 0.0f);
  for (size_t i = 0; i < budget.pixels.size(); ++i) out->near_mask.pixels[i] = budget.pixels[i] != kOneSample;
  return budget;
}

}  // namespace lt

// Which pixels get the sample budget, and with what first batch
// (FrameRenderer::SampleBudgets), and which of the beam's pixels lie at a
// geometric edge (FrameRenderer::EdgePixels).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

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
// `in`, else 0: separably, along the rows, then along the columns of that,
// each by the last set pixel seen (one test of `in` a pixel, whatever the radius).
template <typename In>
Image<uint8_t> Dilate(int w, int h, int radius, In&& in) {
  Image<uint8_t> along_rows(w, h, 1, 0), out(w, h, 1, 0);
  tbb::parallel_for(0, h, [&](int y) {
    int last = -radius - 1;  // the last x' <= x + radius with in(x', y)
    for (int xx = 0; xx < std::min(w, radius); ++xx)
      if (in(xx, y)) last = xx;
    for (int x = 0; x < w; ++x) {
      if (x + radius < w && in(x + radius, y)) last = x + radius;
      along_rows.At(x, y) = last >= x - radius;
    }
  });
  constexpr int kColumns = 64;  // columns a task, run down together
  tbb::parallel_for(0, (w + kColumns - 1) / kColumns, [&](int block) {
    const int x0 = block * kColumns, x1 = std::min(w, x0 + kColumns);
    int last[kColumns];  // per column, the last y' <= y + radius with along_rows set
    std::fill(last, last + kColumns, -radius - 1);
    for (int yy = 0; yy < std::min(h, radius); ++yy)
      for (int x = x0; x < x1; ++x)
        if (along_rows.At(x, yy)) last[x - x0] = yy;
    for (int y = 0; y < h; ++y) {
      const int yr = y + radius;
      for (int x = x0; x < x1; ++x) {
        if (yr < h && along_rows.At(x, yr)) last[x - x0] = yr;
        out.At(x, y) = last[x - x0] >= y - radius;
      }
    }
  });
  return out;
}

// EdgePixels where `wanted(x, y)`, 0 elsewhere.
template <typename Wanted>
Image<uint8_t> EdgesWhere(const Camera& cam, std::span<const ChiefHit> hits, const Eigen::Vector3d& camera_origin,
                          Wanted&& wanted) {
  const int w = cam.width(), h = cam.height();
  const double footprint_per_m = cam.pixel_pitch_m() / cam.image_distance_m();
  auto hit = [&](int x, int y) -> const ChiefHit& { return hits[size_t(y) * size_t(w) + size_t(x)]; };
  // Normals facing the camera, so that the two sides of a thin surface agree.
  auto facing = [&](const ChiefHit& c) {
    Eigen::Vector3d n = c.normal;
    if (c.valid && n.dot(camera_origin - c.p_world) < 0) n = -n;
    return n;
  };
  Image<uint8_t> edge(w, h, 1, 0);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      if (!wanted(x, y)) continue;
      const ChiefHit& c = hit(x, y);
      const Eigen::Vector3d n = facing(c);
      const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
        const ChiefHit& o = hit(nx[k], ny[k]);
        if (AcrossEdge(c, n, o, facing(o), footprint_per_m)) {
          edge.At(x, y) = 1;
          break;
        }
      }
    }
  });
  return edge;
}

}  // namespace

Image<uint8_t> FrameRenderer::EdgePixels(std::span<const ChiefHit> hits, const Eigen::Vector3d& camera_origin) const {
  return EdgesWhere(scene_.sensor.camera, hits, camera_origin, [](int, int) { return true; });
}

Image<uint8_t> FrameRenderer::SampleBudgets(const Image<uint8_t>& reach, std::span<const ChiefHit> hits,
                                            bool all_pixels, RenderedFrame* out) const {
  const Camera& cam = scene_.sensor.camera;
  const int w = cam.width(), h = cam.height();
  Image<uint8_t> budget(w, h, 1, all_pixels ? kBeamBudget : kOneSample);
  out->near_mask = Image<float>(w, h, 1, all_pixels ? 1.0f : 0.0f);
  if (!all_pixels) {
    // The beam's pixels dilated by one pixel plus the largest defocus blur radius
    // seen in the frame; the rest of the glow's pixels.
    std::vector<double> row_coc(size_t(h), 0.0);
    if (!cam.is_pinhole()) {
      tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
          const float z = out->gt.depth.At(x, y);
          if (z > 0) row_coc[size_t(y)] = std::max(row_coc[size_t(y)], cam.CircleOfConfusionPx(z));
        }
      });
    }
    const double max_coc = h > 0 ? *std::max_element(row_coc.begin(), row_coc.end()) : 0.0;
    const int radius = 1 + int(std::ceil(0.5 * max_coc));
    // A square dilation of the beam's pixels; the rest of the glow's pixels.
    const Image<uint8_t> beam = Dilate(w, h, radius, [&](int x, int y) { return reach.At(x, y) >= kInBeam; });
    tbb::parallel_for(0, h, [&](int y) {
      for (int x = 0; x < w; ++x) {
        budget.At(x, y) = beam.At(x, y) ? kBeamBudget : reach.At(x, y) == kInGlow ? kGlowBudget : kOneSample;
        out->near_mask.At(x, y) = budget.At(x, y) != kOneSample;
      }
    });
    if (edge_spp_ > spp_) {
      // Beam pixels within kEdgeDilation of an edge pixel and within
      // kEdgeDilation plus the beam's radius of the sheet itself: where the
      // stripe crosses an edge and the laser's reflection off one face lands on
      // the other. The beam's wider part (the glow's half-energy radius), seen
      // across a printed part's bead valleys, would be edge pixels nearly all.
      const Image<uint8_t> near_sheet =
          Dilate(w, h, radius + kEdgeDilation, [&](int x, int y) { return reach.At(x, y) == kInSheet; });
      auto candidate = [&](int x, int y) { return budget.At(x, y) == kBeamBudget && near_sheet.At(x, y) != 0; };
      // Edges are looked for only within kEdgeDilation of a candidate, where they count.
      const Image<uint8_t> wanted = Dilate(w, h, kEdgeDilation, candidate);
      const Image<uint8_t> edge = EdgesWhere(cam, hits, out->world_from_cam.translation(),
                                             [&](int x, int y) { return wanted.At(x, y) != 0; });
      const Image<uint8_t> near_edge = Dilate(w, h, kEdgeDilation, [&](int x, int y) { return edge.At(x, y) != 0; });
      tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x)
          if (candidate(x, y) && near_edge.At(x, y)) budget.At(x, y) = kEdgeBudget;
      });
    }
  }
  return budget;
}

}  // namespace lt

// Checkerboard corner detection at one smoothing scale
// (pipeline/calib_corner_at_scale.h): steps 1 to 5 of pipeline/calib_corners.h.
#include "pipeline/calib_corner_at_scale.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "pipeline/calib_corner_candidates.h"
#include "pipeline/gaussian_filter.h"
#include "pipeline/option_checks.h"

namespace lt {
namespace corner_detail {

namespace {

double Percentile(std::vector<float> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + ptrdiff_t(k), v.end());
  return v[k];
}

}  // namespace

// The detection at one smoothing scale, on the image already averaged to one
// channel and with its noise estimated.
ScaleResult DetectAtScale(const Image<float>& img, double noise, const CheckerboardSpec& board,
                          const CornerDetectionOptions& options, double sigma) {
  ScaleResult out;
  CornerDetection& det = out.det;
  det.sigma_px = sigma;
  auto refuse = [&](Failure failure, std::string reason) {
    det.ok = false;
    det.reason = std::move(reason);
    det.corners.clear();
    det.corner_std_px.clear();
    out.failure = failure;
    return out;
  };
  const ImageView<float> iv = img.View();
  const int w = img.width, h = img.height;

  // ---- noise and contrast
  det.noise_sigma = noise;
  const GaussianKernels kernels(sigma);
  const Smoothed sm = Smooth(img, kernels);
  // The contrast: the range of the smoothed image between its 0.1st and
  // 99.9th percentiles (smoothing divides the noise by ~5σ; a board covering
  // a few percent of the image still counts, a few hot pixels do not).
  double dark = 0;
  {
    std::vector<float> values;
    const size_t step = std::max<size_t>(1, sm.r.size() / 1000000);
    for (size_t k = 0; k < sm.r.size(); k += step) values.push_back(sm.r[k]);
    dark = Percentile(values, 0.001);
    det.contrast = Percentile(values, 0.999) - dark;
  }
  if (!(det.contrast > 5 * noise) || !(det.contrast > 0)) {
    return refuse(Failure::kNoContrast, "no checkerboard found: the image has no contrast above its noise (contrast " + Fmt(det.contrast) +
                  ", noise " + Fmt(noise) + ")");
  }

  // ---- saddle candidates
  // Each corner is judged against its own contrast (the range of the smoothed
  // image on the validation circle), so that uneven light and vignetting do
  // not matter. That range must exceed 3 noise σ, and a tenth of the light on
  // the corner (its brightest value on the circle above the image's dark
  // level): faint texture is no board, however bright.
  const ContrastFloor floor{3 * noise, dark};
  out.floor = floor;
  const double sigma_eff2 = sigma * sigma + 1.0 / 6.0;  // Gaussian, the kernel's pixel box and the pixel's own
  const double circle = 2.5 * sigma + 1;                 // validation circle radius
  auto response_floor = [&](double range) { return std::pow(options.min_response * range / (M_PI * sigma_eff2), 2); };
  const double threshold = response_floor(floor.noise_floor);  // the lowest floor: dim corners too
  const double border = 2 * sigma + 2;
  const int nms = std::max(1, int(std::lround(sigma)));
  const std::vector<float>& strength = sm.strength;
  // The local maxima of each row, judged in parallel (each alone, from the
  // smoothed image), then taken in scan order: the result does not depend on
  // the threads.
  const int b0 = int(std::ceil(border));
  std::vector<std::vector<Candidate>> row_cands(size_t(std::max(0, h)));
  tbb::parallel_for(tbb::blocked_range<int>(b0, std::max(b0, h - b0), 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = b0; x < w - b0; ++x) {
        const float s = strength[size_t(y) * size_t(w) + size_t(x)];
        if (!(s > threshold)) continue;
        bool is_max = true;
        for (int dy = -nms; dy <= nms && is_max; ++dy) {
          for (int dx = -nms; dx <= nms; ++dx) {
            if (dx == 0 && dy == 0) continue;
            const float o = strength[size_t(y + dy) * size_t(w) + size_t(x + dx)];
            // Ties: the first in scan order wins.
            if (o > s || (o == s && (dy < 0 || (dy == 0 && dx < 0)))) {
              is_max = false;
              break;
            }
          }
        }
        if (!is_max) continue;
        Candidate c;
        c.p = Eigen::Vector2d(x, y);
        c.strength = s;
        double ring[kCircleSamples];
        const double range = CircleSamples(sm, c.p, circle, ring);
        const double brightest = *std::max_element(ring, ring + kCircleSamples);
        if (!(range >= floor.For(brightest)) || !(s > response_floor(range))) continue;
        if (!RefineSaddle(iv, sigma, kernels.radius, border, &c.p, &c.hessian)) continue;
        if (!EdgeDirections(sm, c.p, circle, floor, &c)) continue;
        row_cands[size_t(y)].push_back(c);
      }
    }
  });
  std::vector<Candidate> cands;
  for (const std::vector<Candidate>& row : row_cands) {
    for (const Candidate& c : row) {
      bool duplicate = false;
      for (const auto& o : cands) duplicate = duplicate || (o.p - c.p).norm() < 1.0;
      if (!duplicate) cands.push_back(c);
    }
  }
  det.candidates = int(cands.size());
  if (cands.size() < 4) {
    return refuse(Failure::kFewCandidates, "no checkerboard found: " + std::to_string(cands.size()) + " corner-like points in the image");
  }

  // ---- grid, from the strongest seeds
  std::vector<int> order(cands.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = int(k);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return cands[size_t(a)].strength > cands[size_t(b)].strength; });
  Grid best;
  std::vector<char> tried(cands.size(), 0);
  int seeds = 0;
  bool complete = false;
  int ni = 0, amin = 0, bmin = 0;
  for (int seed : order) {
    if (seeds >= options.max_seeds) break;
    if (tried[size_t(seed)]) continue;
    ++seeds;
    Grid g = GrowGrid(cands, seed, options.neighbour_tolerance);
    for (const auto& [cell, idx] : g.cells) tried[size_t(idx)] = 1;
    // A grid larger than the board: corner-like points beyond the squares
    // (a narrow margin against a dark background) may have joined it.
    if (!Extent(g).FitsIn(board)) DropCornersBeyondSquares(&g, cands, sm, floor);
    if (g.cells.size() > best.cells.size()) best = g;
    const GridExtent e = Extent(g);
    if (e.full && e.Matches(board)) {
      best = g;
      complete = true;
      ni = e.rows, amin = e.a0, bmin = e.c0;
      break;
    }
  }
  for (const auto& [cell, idx] : best.cells) det.grid.push_back({cands[size_t(idx)].p, cell.first, cell.second});
  if (!complete) {
    if (best.cells.size() < 4) return refuse(Failure::kNoGrid, "no checkerboard found: no grid of corners");
    const GridExtent e = Extent(best);
    const Failure failure = GridFailure(best, cands, board, w, h, border, circle);
    const std::string off_edges = EdgesTheGridRunsOff(best, cands, w, h, border);
    const std::string why =
        !e.FitsIn(board) ? "more corners along a line than the board: a board of another size, or corner-like "
                           "points beyond its edge joined the grid"
        : failure == Failure::kGridNotTheBoard
            ? "a whole grid of another size, or a board whose outer corners are hidden"
        : !off_edges.empty()
            ? "the board is partly outside the image (the grid runs off its " + off_edges + " edge" +
                  (off_edges.find(" and ") == std::string::npos ? "" : "s") +
                  "), or occluded, or too small or blurred for sigma_px = " + Fmt(sigma)
            : "the board is partly outside the image, occluded, or too small or blurred for sigma_px = " + Fmt(sigma);
    return refuse(failure, "found a grid of " + std::to_string(best.cells.size()) + " corners (" +
                               std::to_string(e.rows) + " x " + std::to_string(e.cols) + (e.full ? "" : " with holes") +
                               "), not the complete " + std::to_string(board.rows) + " x " +
                               std::to_string(board.cols) + " board: " + why);
  }

  // ---- board order: rows/cols by count, handedness, then colour
  auto local = [&](int i, int j) -> const Candidate& {
    // Board (i, j) before flips -> the grid's own cell.
    const Cell c = ni == board.rows ? Cell{amin + i, bmin + j} : Cell{amin + j, bmin + i};
    return cands[size_t(best.cells.at(c))];
  };
  const int R = board.rows, C = board.cols;
  bool flip_j = false, flip_both = false;
  auto at = [&](int i, int j) -> const Candidate& {
    if (flip_both) i = R - 1 - i, j = C - 1 - j;
    if (flip_j) j = C - 1 - j;
    return local(i, j);
  };
  Eigen::Vector2d along_row = Eigen::Vector2d::Zero(), along_col = Eigen::Vector2d::Zero();
  for (int i = 0; i < R; ++i)
    for (int j = 0; j + 1 < C; ++j) along_row += at(i, j + 1).p - at(i, j).p;
  for (int i = 0; i + 1 < R; ++i)
    for (int j = 0; j < C; ++j) along_col += at(i + 1, j).p - at(i, j).p;
  // Seen from the front, board x (along a row) then y (down a column) turn
  // clockwise in the image (y down): a positive cross product.
  if (along_row.x() * along_col.y() - along_row.y() * along_col.x() < 0) flip_j = true;
  // Colour: each square against its right and lower neighbours (a local
  // comparison, whatever the lighting across the board). Squares with i + j
  // even are black.
  std::vector<double> square((R - 1) * (C - 1));
  for (int i = 0; i + 1 < R; ++i) {
    for (int j = 0; j + 1 < C; ++j) {
      const Eigen::Vector2d centre = 0.25 * (at(i, j).p + at(i + 1, j).p + at(i, j + 1).p + at(i + 1, j + 1).p);
      square[size_t(i * (C - 1) + j)] = sm.Sample(centre.x(), centre.y());
    }
  }
  int even_darker = 0, odd_darker = 0, pairs = 0;
  for (int i = 0; i + 1 < R; ++i) {
    for (int j = 0; j + 1 < C; ++j) {
      for (const auto& [i2, j2] : {std::pair{i, j + 1}, std::pair{i + 1, j}}) {
        if (i2 + 1 >= R || j2 + 1 >= C) continue;
        const double v = square[size_t(i * (C - 1) + j)], u = square[size_t(i2 * (C - 1) + j2)];
        const double even_minus_odd = (i + j) % 2 == 0 ? v - u : u - v;
        ++pairs;
        const double pair_floor = floor.For(std::max(v, u));
        if (even_minus_odd < -pair_floor) ++even_darker;
        if (even_minus_odd > pair_floor) ++odd_darker;
      }
    }
  }
  // All neighbouring pairs but a few (a reflection, a stain) must agree.
  if (!(std::max(even_darker, odd_darker) >= std::max(1, (3 * pairs + 3) / 4))) {
    return refuse(Failure::kColours, "the squares' colours do not tell the board's orientation (of " + std::to_string(pairs) +
                  " pairs of neighbouring squares, " + std::to_string(even_darker) + " say one way, " +
                  std::to_string(odd_darker) + " the other)");
  }
  if (odd_darker > even_darker) flip_both = true;

  // ---- output, with the predicted standard deviations
  det.grid.clear();
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < C; ++j) {
      const Candidate& c = at(i, j);
      det.corners.push_back(c.p);
      det.corner_std_px.push_back(SaddleStdPx(kernels, noise, c.hessian));
      det.grid.push_back({c.p, i, j});
    }
  }
  det.ok = true;
  return out;
}

}  // namespace corner_detail
}  // namespace lt

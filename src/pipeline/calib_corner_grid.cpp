// Checkerboard corner detection's grid (pipeline/calib_corner_grid.h): growing
// it from a seed, why a grid is refused, the off-grid test of a corner.
#include "pipeline/calib_corner_grid.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace lt {
namespace corner_detail {

namespace {

// Whether direction d (unit) runs along one of the candidate's edges (within 20 degrees).
bool AlongEdge(const Candidate& c, const Eigen::Vector2d& d) {
  const double cmin = std::cos(20 * M_PI / 180);
  return std::abs(c.e1.dot(d)) > cmin || std::abs(c.e2.dot(d)) > cmin;
}

}  // namespace

Grid GrowGrid(const std::vector<Candidate>& cands, int seed, double tolerance) {
  Grid g;
  const Candidate& s = cands[size_t(seed)];
  std::vector<char> used(cands.size(), 0);
  auto nearest_along = [&](const Eigen::Vector2d& dir) {
    int best = -1;
    double best_d = HUGE_VAL;
    for (size_t k = 0; k < cands.size(); ++k) {
      if (int(k) == seed) continue;
      const Eigen::Vector2d d = cands[k].p - s.p;
      const double len = d.norm();
      if (len < 3 || len >= best_d) continue;
      if (d.dot(dir) < len * std::cos(15 * M_PI / 180)) continue;
      best = int(k), best_d = len;
    }
    return best;
  };
  g.cells[{0, 0}] = seed;
  used[size_t(seed)] = 1;
  int n[4] = {nearest_along(s.e1), nearest_along(-s.e1), nearest_along(s.e2), nearest_along(-s.e2)};
  const Cell at[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  // The two neighbours along one edge are about equally far (perspective
  // changes the spacing by far less than the tolerance allows): of two very
  // different ones, the farther lies beyond the board's edge (another
  // object's corner) and is dropped.
  for (int k = 0; k < 4; k += 2) {
    if (n[k] < 0 || n[k + 1] < 0) continue;
    const double d0 = (cands[size_t(n[k])].p - s.p).norm(), d1 = (cands[size_t(n[k + 1])].p - s.p).norm();
    if (std::max(d0, d1) > std::min(d0, d1) * (1 + tolerance) / (1 - tolerance)) n[d0 > d1 ? k : k + 1] = -1;
  }
  if ((n[0] < 0 && n[1] < 0) || (n[2] < 0 && n[3] < 0)) return g;
  for (int k = 0; k < 4; ++k) {
    if (n[k] >= 0 && !used[size_t(n[k])]) {
      g.cells[at[k]] = n[k];
      used[size_t(n[k])] = 1;
    }
  }
  auto pos = [&](const Cell& c) -> const Eigen::Vector2d* {
    auto it = g.cells.find(c);
    return it == g.cells.end() ? nullptr : &cands[size_t(it->second)].p;
  };
  const Cell dirs[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (bool changed = true; changed;) {
    changed = false;
    const std::vector<std::pair<Cell, int>> snapshot(g.cells.begin(), g.cells.end());
    for (const auto& [cell, idx] : snapshot) {
      for (const Cell& d : dirs) {
        const Cell target{cell.first + d.first, cell.second + d.second};
        if (g.cells.count(target)) continue;
        const Eigen::Vector2d& p = cands[size_t(idx)].p;
        Eigen::Vector2d pred;
        double step = 0;
        if (const auto* back = pos({cell.first - d.first, cell.second - d.second})) {
          pred = 2 * p - *back;
          step = (p - *back).norm();
        } else {
          bool found = false;
          for (int sgn : {1, -1}) {
            const Cell perp{d.second * sgn, d.first * sgn};
            const auto* tp = pos({target.first + perp.first, target.second + perp.second});
            const auto* cp = pos({cell.first + perp.first, cell.second + perp.second});
            if (tp && cp) {
              pred = p + (*tp - *cp);
              step = (*tp - *cp).norm();
              found = true;
              break;
            }
          }
          if (!found) continue;
        }
        int best = -1;
        double best_d = tolerance * step;
        for (size_t k = 0; k < cands.size(); ++k) {
          if (used[k]) continue;
          const double dist = (cands[k].p - pred).norm();
          if (dist < best_d) best = int(k), best_d = dist;
        }
        if (best < 0) continue;
        const Eigen::Vector2d along = (cands[size_t(best)].p - p).normalized();
        if (!AlongEdge(cands[size_t(best)], along) || !AlongEdge(cands[size_t(idx)], along)) continue;
        g.cells[target] = best;
        used[size_t(best)] = 1;
        changed = true;
      }
    }
  }
  return g;
}

void DropCornersBeyondSquares(Grid* g, const std::vector<Candidate>& cands, const Smoothed& sm,
                              const ContrastFloor& floor) {
  auto pos = [&](const Cell& c) -> const Eigen::Vector2d* {
    auto it = g->cells.find(c);
    return it == g->cells.end() ? nullptr : &cands[size_t(it->second)].p;
  };
  for (bool dropped = true; dropped && !g->cells.empty();) {
    dropped = false;
    const GridExtent e = Extent(*g);
    const int a1 = e.a0 + e.rows - 1, c1 = e.c0 + e.cols - 1;
    std::vector<Cell> drop;
    for (const auto& [cell, idx] : g->cells) {
      const Eigen::Vector2d& p = cands[size_t(idx)].p;
      std::vector<Cell> outward;
      if (cell.first == e.a0) outward.push_back({-1, 0});
      if (cell.first == a1) outward.push_back({1, 0});
      if (cell.second == e.c0) outward.push_back({0, -1});
      if (cell.second == c1) outward.push_back({0, 1});
      for (const Cell& d : outward) {
        const auto* inner = pos({cell.first - d.first, cell.second - d.second});
        if (!inner) continue;  // nothing to take the step from
        const Cell u{d.second, d.first};  // along the line
        // The step along the line: from the corner's neighbours on it, or
        // else from its inner neighbour's.
        Eigen::Vector2d along;
        const Cell in{cell.first - d.first, cell.second - d.second};
        if (const auto* n = pos({cell.first + u.first, cell.second + u.second})) {
          along = *n - p;
        } else if (const auto* m = pos({cell.first - u.first, cell.second - u.second})) {
          along = p - *m;
        } else if (const auto* ni = pos({in.first + u.first, in.second + u.second})) {
          along = *ni - *inner;
        } else if (const auto* mi = pos({in.first - u.first, in.second - u.second})) {
          along = *inner - *mi;
        } else {
          continue;
        }
        // The cells on either side of the corner along the line, outside
        // (v) and inside (w): a board's corner has squares of opposite
        // colours diagonally, so v1 - v2 has the opposite sign of w1 - w2
        // and about its size (the light changes little over one square).
        const Eigen::Vector2d half_out = 0.5 * (p - *inner), half_along = 0.5 * along;
        auto at = [&](const Eigen::Vector2d& q) { return sm.Sample(q.x(), q.y()); };
        const double v1 = at(p + half_out + half_along), v2 = at(p + half_out - half_along);
        const double w1 = at(p - half_out + half_along), w2 = at(p - half_out - half_along);
        if (!((v1 - v2) * (w1 - w2) < 0 && std::abs(v1 - v2) >= 0.5 * std::abs(w1 - w2) &&
              std::abs(v1 - v2) >= floor.For(std::max(v1, v2)))) {
          drop.push_back(cell);
          break;
        }
      }
    }
    for (const Cell& c : drop) g->cells.erase(c);
    dropped = !drop.empty();
  }
}

// An incomplete grid is refused for good (no other scale tried) when it
// cannot be a part of the board that another scale would complete: a grid
// without holes that has more corners along a line than the board (a board of
// another size, or another board), or one whose squares are large for this
// scale and whose next corners beyond each side would still be well inside
// the image (a whole board of another size, or a board whose outer corners
// are occluded). Otherwise (holes, squares small against the kernel, or a
// grid cut by the image border) another scale may find the rest.
GridExtent Extent(const Grid& g) {
  int a0 = 1 << 30, a1 = -(1 << 30), c0 = 1 << 30, c1 = -(1 << 30);
  for (const auto& [cell, idx] : g.cells) {
    a0 = std::min(a0, cell.first), a1 = std::max(a1, cell.first);
    c0 = std::min(c0, cell.second), c1 = std::max(c1, cell.second);
  }
  GridExtent e;
  e.a0 = a0, e.c0 = c0, e.rows = a1 - a0 + 1, e.cols = c1 - c0 + 1;
  e.full = int(g.cells.size()) == e.rows * e.cols;
  return e;
}

Failure GridFailure(const Grid& g, const std::vector<Candidate>& cands, const CheckerboardSpec& board, int w, int h,
                    double border, double circle) {
  const GridExtent e = Extent(g);
  const int a0 = e.a0, a1 = e.a0 + e.rows - 1, c0 = e.c0, c1 = e.c0 + e.cols - 1;
  const int da = e.rows, dc = e.cols;
  if (!e.full) return Failure::kIncompleteGrid;  // holes
  if (!e.FitsIn(board)) return Failure::kGridNotTheBoard;
  auto p = [&](int a, int c) { return cands[size_t(g.cells.at({a, c}))].p; };
  double spacing = HUGE_VAL;
  bool inside = true;
  auto check_next = [&](const Eigen::Vector2d& edge, const Eigen::Vector2d& inner) {
    const Eigen::Vector2d next = 2 * edge - inner;
    inside = inside && next.x() >= border + circle && next.y() >= border + circle && next.x() <= w - 1 - border - circle &&
             next.y() <= h - 1 - border - circle;
  };
  for (int a = a0; a <= a1; ++a) {
    for (int c = c0; c <= c1; ++c) {
      if (a < a1) spacing = std::min(spacing, (p(a + 1, c) - p(a, c)).norm());
      if (c < c1) spacing = std::min(spacing, (p(a, c + 1) - p(a, c)).norm());
    }
  }
  if (da >= 2) {
    for (int c = c0; c <= c1; ++c) check_next(p(a0, c), p(a0 + 1, c)), check_next(p(a1, c), p(a1 - 1, c));
  }
  if (dc >= 2) {
    for (int a = a0; a <= a1; ++a) check_next(p(a, c0), p(a, c0 + 1)), check_next(p(a, c1), p(a, c1 - 1));
  }
  if (da >= 2 && dc >= 2 && inside && spacing >= 2 * circle) return Failure::kGridNotTheBoard;
  return Failure::kIncompleteGrid;
}

std::string EdgesTheGridRunsOff(const Grid& g, const std::vector<Candidate>& cands, int w, int h, double border) {
  bool off[4] = {false, false, false, false};  // left, right, top, bottom
  for (const auto& [cell, idx] : g.cells) {
    for (const Cell& d : {Cell{1, 0}, Cell{-1, 0}, Cell{0, 1}, Cell{0, -1}}) {
      if (g.cells.count({cell.first + d.first, cell.second + d.second})) continue;
      const auto back = g.cells.find({cell.first - d.first, cell.second - d.second});
      if (back == g.cells.end()) continue;
      const Eigen::Vector2d next = 2 * cands[size_t(idx)].p - cands[size_t(back->second)].p;
      off[0] = off[0] || next.x() < border;
      off[1] = off[1] || next.x() > w - 1 - border;
      off[2] = off[2] || next.y() < border;
      off[3] = off[3] || next.y() > h - 1 - border;
    }
  }
  std::string edges;
  const char* names[4] = {"left", "right", "top", "bottom"};
  for (int k = 0; k < 4; ++k) {
    if (off[k]) edges += (edges.empty() ? "" : " and ") + std::string(names[k]);
  }
  return edges;
}

// Where the homography through the neighbours of corner (i, j) (those within
// one square, or two when fewer than five) puts it. Perspective keeps the
// board's corners on a homography; lens distortion bends it little over two
// squares.
bool GridPrediction(const std::vector<Eigen::Vector2d>& corners, int rows, int cols, int i, int j,
                    Eigen::Vector2d* predicted, const std::vector<char>* left_out) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> pts;  // (board, image)
  for (int reach = 1; reach <= 2 && pts.size() < 5; ++reach) {
    pts.clear();
    for (int a = std::max(0, i - reach); a <= std::min(rows - 1, i + reach); ++a)
      for (int b = std::max(0, j - reach); b <= std::min(cols - 1, j + reach); ++b)
        if ((a != i || b != j) && !(left_out && (*left_out)[size_t(a * cols + b)]))
          pts.push_back({Eigen::Vector2d(b - j, a - i), corners[size_t(a * cols + b)]});
  }
  if (pts.size() < 5) return false;  // too few neighbours
  // Normalised DLT: image points centred and scaled.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& pr : pts) mean += pr.second;
  mean /= double(pts.size());
  double scale = 0;
  for (const auto& pr : pts) scale += (pr.second - mean).norm();
  scale = scale > 0 ? double(pts.size()) / scale : 1;
  Eigen::MatrixXd a(2 * pts.size(), 9);
  for (size_t k = 0; k < pts.size(); ++k) {
    const double x = pts[k].first.x(), y = pts[k].first.y();
    const Eigen::Vector2d q = (pts[k].second - mean) * scale;
    a.row(2 * k) << x, y, 1, 0, 0, 0, -q.x() * x, -q.x() * y, -q.x();
    a.row(2 * k + 1) << 0, 0, 0, x, y, 1, -q.y() * x, -q.y() * y, -q.y();
  }
  const Eigen::VectorXd h = Eigen::JacobiSVD<Eigen::MatrixXd>(a, Eigen::ComputeFullV).matrixV().col(8);
  if (!(std::abs(h(8)) > 1e-12)) return false;
  *predicted = Eigen::Vector2d(h(2), h(5)) / h(8) / scale + mean;  // board offset (0, 0)
  return predicted->allFinite();
}

double OffGrid(const std::vector<Eigen::Vector2d>& corners, int rows, int cols, int i, int j) {
  int neighbours = 0;
  for (int a = std::max(0, i - 2); a <= std::min(rows - 1, i + 2); ++a)
    for (int b = std::max(0, j - 2); b <= std::min(cols - 1, j + 2); ++b) neighbours += a != i || b != j;
  if (neighbours < 5) return 0;  // too few neighbours to compare with
  Eigen::Vector2d pred;
  if (!GridPrediction(corners, rows, cols, i, j, &pred)) return HUGE_VAL;
  return (pred - corners[size_t(i * cols + j)]).norm();
}

}  // namespace corner_detail
}  // namespace lt

#include "pipeline/calib_corners.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <type_traits>
#include <utility>
#include <variant>

#include "core/error.h"
#include "pipeline/option_checks.h"
#include "pipeline/gaussian_filter.h"

namespace lt {

namespace {

template <typename T>
Image<float> ToFloat(const ImageView<T>& v) {
  Image<float> out(v.width, v.height, 1);
  for (int y = 0; y < v.height; ++y) {
    for (int x = 0; x < v.width; ++x) {
      double s = 0;
      for (int c = 0; c < v.channels; ++c) s += double(v.At(x, y, c));
      out.At(x, y) = float(s / v.channels);
    }
  }
  return out;
}

// Image noise σ: Immerkær's mask [1 −2 1; −2 4 −2; 1 −2 1] responds to white
// noise with standard deviation 6σ and hardly to smooth image content; the
// median of its magnitude (/0.6745 for a normal distribution) ignores edges.
double NoiseSigma(const Image<float>& img) {
  std::vector<float> a;
  const int stride = img.width * img.height > 2000000 ? 2 : 1;
  for (int y = 1; y + 1 < img.height; y += stride) {
    for (int x = 1; x + 1 < img.width; x += stride) {
      auto p = [&](int dx, int dy) { return double(img.At(x + dx, y + dy)); };
      const double r = p(-1, -1) + p(1, -1) + p(-1, 1) + p(1, 1) - 2 * (p(0, -1) + p(0, 1) + p(-1, 0) + p(1, 0)) +
                       4 * p(0, 0);
      a.push_back(float(std::abs(r)));
    }
  }
  if (a.empty()) return 0;
  std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
  return a[a.size() / 2] / 0.6745 / 6.0;
}

double Percentile(std::vector<float> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + ptrdiff_t(k), v.end());
  return v[k];
}

// The smoothed image and its second derivatives, whole image (borders mirrored).
struct Smoothed {
  int w = 0, h = 0;
  std::vector<float> r, rxx, rxy, ryy;
  float At(const std::vector<float>& v, int x, int y) const { return v[size_t(y) * size_t(w) + size_t(x)]; }
  // Bilinear sample of r (clamped to the image).
  double Sample(double x, double y) const {
    x = std::clamp(x, 0.0, w - 1.0);
    y = std::clamp(y, 0.0, h - 1.0);
    const int x0 = std::min(int(x), w - 2 < 0 ? 0 : w - 2), y0 = std::min(int(y), h - 2 < 0 ? 0 : h - 2);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const double fx = x - x0, fy = y - y0;
    return (1 - fy) * ((1 - fx) * At(r, x0, y0) + fx * At(r, x1, y0)) + fy * ((1 - fx) * At(r, x0, y1) + fx * At(r, x1, y1));
  }
};

Smoothed Smooth(const Image<float>& img, const GaussianKernels& k) {
  Smoothed s;
  s.w = img.width, s.h = img.height;
  const int w = s.w, h = s.h, R = k.radius;
  const size_t n = size_t(w) * size_t(h);
  std::vector<float> h0(n), h1(n), h2(n), row(size_t(w + 2 * R));
  for (int y = 0; y < h; ++y) {
    for (int x = -R; x < w + R; ++x) row[size_t(x + R)] = img.At(MirrorIndex(x, w), y);
    float* o0 = &h0[size_t(y) * size_t(w)];
    float* o1 = &h1[size_t(y) * size_t(w)];
    float* o2 = &h2[size_t(y) * size_t(w)];
    for (int x = 0; x < w; ++x) o0[x] = o1[x] = o2[x] = 0;
    // out[x] = Σ_o in[x − o] K(o): derivatives of Σ_m in[m] K0(x − m).
    for (int o = -R; o <= R; ++o) {
      const float c0 = k.k0[size_t(o + R)], c1 = k.k1[size_t(o + R)], c2 = k.k2[size_t(o + R)];
      const float* in = &row[size_t(R - o)];
      for (int x = 0; x < w; ++x) {
        o0[x] += in[x] * c0;
        o1[x] += in[x] * c1;
        o2[x] += in[x] * c2;
      }
    }
  }
  s.r.assign(n, 0);
  s.rxx.assign(n, 0);
  s.rxy.assign(n, 0);
  s.ryy.assign(n, 0);
  for (int y = 0; y < h; ++y) {
    float* r = &s.r[size_t(y) * size_t(w)];
    float* rxx = &s.rxx[size_t(y) * size_t(w)];
    float* rxy = &s.rxy[size_t(y) * size_t(w)];
    float* ryy = &s.ryy[size_t(y) * size_t(w)];
    for (int o = -R; o <= R; ++o) {
      const size_t src = size_t(MirrorIndex(y - o, h)) * size_t(w);
      const float c0 = k.k0[size_t(o + R)], c1 = k.k1[size_t(o + R)], c2 = k.k2[size_t(o + R)];
      const float *a0 = &h0[src], *a1 = &h1[src], *a2 = &h2[src];
      for (int x = 0; x < w; ++x) {
        r[x] += a0[x] * c0;
        rxx[x] += a2[x] * c0;
        rxy[x] += a1[x] * c1;
        ryy[x] += a0[x] * c2;
      }
    }
  }
  return s;
}

struct Candidate {
  Eigen::Vector2d p;
  double strength = 0;
  Eigen::Vector2d e1, e2;  // unit directions of the two edges through the corner
  Eigen::Matrix2d hessian;
};

// Newton's method on the gradient of the smoothed image: the saddle point.
bool RefineSaddle(const ImageView<float>& img, double sigma, int radius, double border, Eigen::Vector2d* p,
                  Eigen::Matrix2d* hessian) {
  const Eigen::Vector2d start = *p;
  for (int it = 0; it < 30; ++it) {
    const SmoothedDerivatives d = SmoothedDerivativesAt(img, p->x(), p->y(), sigma, radius);
    Eigen::Matrix2d hm;
    hm << d.rxx, d.rxy, d.rxy, d.ryy;
    if (!(hm.determinant() < 0)) return false;
    Eigen::Vector2d step = -hm.inverse() * Eigen::Vector2d(d.rx, d.ry);
    if (step.norm() > 0.5) step *= 0.5 / step.norm();
    *p += step;
    if ((*p - start).norm() > 2.0) return false;
    if (p->x() < border || p->y() < border || p->x() > img.width - 1 - border || p->y() > img.height - 1 - border) {
      return false;
    }
    if (step.norm() < 1e-6) {
      *hessian = hm;
      return true;
    }
  }
  return false;
}

// Four dark/bright changes on a circle around the corner, at two pairs of
// nearly opposite angles: the two edges.
constexpr int kCircleSamples = 48;

// The smoothed image on a circle around p; returns its range (max − min).
double CircleSamples(const Smoothed& s, const Eigen::Vector2d& p, double radius, double* v) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int k = 0; k < kCircleSamples; ++k) {
    const double a = 2 * M_PI * k / kCircleSamples;
    v[k] = s.Sample(p.x() + radius * std::cos(a), p.y() + radius * std::sin(a));
    lo = std::min(lo, v[k]);
    hi = std::max(hi, v[k]);
  }
  return hi - lo;
}

// The edges from the smoothed image sampled on the circle (kCircleSamples
// values, counter-clockwise from +x).
bool EdgeDirectionsOnRing(const double* v, double min_range, Candidate* c) {
  constexpr int kSamples = kCircleSamples;
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int k = 0; k < kSamples; ++k) lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
  if (!(hi - lo >= min_range)) return false;
  const double mid = 0.5 * (lo + hi);
  std::vector<double> t;
  for (int k = 0; k < kSamples; ++k) {
    const double a = v[k] - mid, b = v[(k + 1) % kSamples] - mid;
    if ((a > 0) != (b > 0)) t.push_back(2 * M_PI * (k + a / (a - b)) / kSamples);
  }
  if (t.size() != 4) return false;
  auto off_pi = [](double d) { return std::abs(std::remainder(d - M_PI, 2 * M_PI)); };
  constexpr double kTol = 30 * M_PI / 180;
  if (off_pi(t[2] - t[0]) > kTol || off_pi(t[3] - t[1]) > kTol) return false;
  // Average each pair as lines (doubled angles).
  auto line = [](double a, double b) {
    const double x = std::cos(2 * a) + std::cos(2 * b), y = std::sin(2 * a) + std::sin(2 * b);
    const double ang = 0.5 * std::atan2(y, x);
    return Eigen::Vector2d(std::cos(ang), std::sin(ang));
  };
  c->e1 = line(t[0], t[2]);
  c->e2 = line(t[1], t[3]);
  return std::abs(c->e1.dot(c->e2)) < std::cos(15 * M_PI / 180);
}

bool EdgeDirections(const Smoothed& s, const Eigen::Vector2d& p, double radius, double min_range, Candidate* c) {
  double v[kCircleSamples];
  CircleSamples(s, p, radius, v);
  return EdgeDirectionsOnRing(v, min_range, c);
}

// Whether the image smoothed at `sigma` (smaller than the scale `found_sigma`
// a corner was found at) has the corner's saddle too: Newton's method from p
// converges within 0.05 px + 4 times the predicted standard deviation of the
// two (noise only), to a saddle of at least min_response of the ideal
// response at the larger scale, with the X of step 3 on the validation circle
// of the smaller scale. A larger kernel averages the surroundings of the
// corner: it makes a saddle, up to a pixel or two off, where a small occluder
// hides the corner, and there the smaller scale sees no saddle. Blur does not
// remove the saddle at the smaller scale; it weakens it by at most the ratio
// of the two scales' squares.
bool SaddleAtScale(const ImageView<float>& img, const Eigen::Vector2d& p, double p_std, double sigma, double found_sigma,
                   double noise, double min_range, double min_response) {
  const GaussianKernels kernels(sigma);
  Eigen::Vector2d q = p;
  Eigen::Matrix2d hessian;
  if (!RefineSaddle(img, sigma, kernels.radius, 2 * sigma + 2, &q, &hessian)) return false;
  // The two saddles differ by the noise (the predicted standard deviations
  // of both) and by a few hundredths of a pixel of model error.
  double kg = 0, k0 = 0;
  for (float v : kernels.k1) kg += double(v) * v;
  for (float v : kernels.k0) k0 += double(v) * v;
  const Eigen::Matrix2d hinv = hessian.inverse();
  const double q_var = noise * noise * kg * k0 * (hinv * hinv.transpose()).trace() / 2;
  const double tol = 0.05 + 4 * std::sqrt(q_var + p_std * p_std);
  if (!((q - p).norm() <= tol)) return false;
  const double circle = 2.5 * sigma + 1;
  double v[kCircleSamples], lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int k = 0; k < kCircleSamples; ++k) {
    const double a = 2 * M_PI * k / kCircleSamples;
    v[k] = SmoothedDerivativesAt(img, q.x() + circle * std::cos(a), q.y() + circle * std::sin(a), sigma, kernels.radius).r;
    lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
  }
  const double ideal = (hi - lo) / (M_PI * (found_sigma * found_sigma + 1.0 / 6.0));
  if (!(std::sqrt(std::max(0.0, -hessian.determinant())) >= min_response * ideal)) return false;
  Candidate c;
  return EdgeDirectionsOnRing(v, min_range, &c);
}

// How far corner (i, j) of a rows x cols detection lies from where the
// homography through its neighbours (those within one square, or two when
// fewer than five) puts it. Perspective keeps the board's corners on a
// homography; lens distortion bends it little over two squares.
double OffGrid(const std::vector<Eigen::Vector2d>& corners, int rows, int cols, int i, int j) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> pts;  // (board, image)
  for (int reach = 1; reach <= 2 && pts.size() < 5; ++reach) {
    pts.clear();
    for (int a = std::max(0, i - reach); a <= std::min(rows - 1, i + reach); ++a)
      for (int b = std::max(0, j - reach); b <= std::min(cols - 1, j + reach); ++b)
        if (a != i || b != j) pts.push_back({Eigen::Vector2d(b - j, a - i), corners[size_t(a * cols + b)]});
  }
  if (pts.size() < 5) return 0;  // too few neighbours to compare with
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
  if (!(std::abs(h(8)) > 1e-12)) return HUGE_VAL;
  const Eigen::Vector2d pred = Eigen::Vector2d(h(2), h(5)) / h(8) / scale + mean;  // board offset (0, 0)
  return (pred - corners[size_t(i * cols + j)]).norm();
}

// Point asymmetry of the image about p within radius r: the RMS difference
// between the image at p + d and at p − d, less its expectation from noise
// and a linear light gradient,
// as a fraction of the range of the image there. The four squares around a
// corner (and the ones beyond) are point-symmetric about it, whatever the
// perspective, and so is any symmetric blur of them (defocus, motion):
// blur and noise leave it near 0; an occluder beside the corner does not.
constexpr double kMaxAsymmetry = 0.05;  // measured: up to 0.03 on boards, 0.08 and more beside occluders

double PointAsymmetry(const Image<float>& img, const Eigen::Vector2d& p, double r, double noise) {
  const int x0 = int(std::floor(p.x())), y0 = int(std::floor(p.y()));
  const double fx = p.x() - x0, fy = p.y() - y0;
  const int R = int(std::ceil(r));
  if (x0 - R - 1 < 0 || y0 - R - 1 < 0 || x0 + R + 2 >= img.width || y0 + R + 2 >= img.height) return HUGE_VAL;
  auto at = [&](int x, int y, double ax, double ay) {
    return (1 - ay) * ((1 - ax) * img.At(x, y) + ax * img.At(x + 1, y)) + ay * ((1 - ax) * img.At(x, y + 1) + ax * img.At(x + 1, y + 1));
  };
  // Uneven light L(p + d) ≈ L(p)(1 + g·d) adds (a + b)/2 · 2g·d to the
  // difference: that part (least squares over g) is taken out.
  double sum = 0, lo = HUGE_VAL, hi = -HUGE_VAL;
  Eigen::Matrix2d ata = Eigen::Matrix2d::Zero();
  Eigen::Vector2d atb = Eigen::Vector2d::Zero();
  int n = 0;
  for (int dy = -R; dy <= R; ++dy) {
    for (int dx = -R; dx <= R; ++dx) {
      if (dx * dx + dy * dy > r * r || dy < 0 || (dy == 0 && dx <= 0)) continue;
      const double a = at(x0 + dx, y0 + dy, fx, fy);
      const double b = at(x0 - dx, y0 - dy, fx, fy);  // p − d
      const Eigen::Vector2d reg = 0.5 * (a + b) * Eigen::Vector2d(dx, dy);
      ata += reg * reg.transpose();
      atb += reg * (a - b);
      sum += (a - b) * (a - b);
      lo = std::min({lo, a, b}), hi = std::max({hi, a, b});
      ++n;
    }
  }
  if (n < 3 || !(hi > lo)) return HUGE_VAL;
  if (std::abs(ata.determinant()) > 0) sum -= atb.dot(ata.inverse() * atb);
  const double w = ((1 - fx) * (1 - fx) + fx * fx) * ((1 - fy) * (1 - fy) + fy * fy);
  return std::sqrt(std::max(0.0, sum / n - 2 * noise * noise * w)) / (hi - lo);
}

using Cell = std::pair<int, int>;

struct Grid {
  std::map<Cell, int> cells;  // (a, b) -> candidate
};

// Whether direction d (unit) runs along one of the candidate's edges (within 20 degrees).
bool AlongEdge(const Candidate& c, const Eigen::Vector2d& d) {
  const double cmin = std::cos(20 * M_PI / 180);
  return std::abs(c.e1.dot(d)) > cmin || std::abs(c.e2.dot(d)) > cmin;
}

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

// Why one scale refused the board: the first three after kNone are what another scale may
// cure (blur, squares small against the kernel); the others no scale cures.
enum class Failure { kNone, kFewCandidates, kNoGrid, kIncompleteGrid, kNoContrast, kGridNotTheBoard, kColours };

// An incomplete grid is refused for good (no other scale tried) when it
// cannot be a part of the board that another scale would complete: a grid
// without holes that has more corners along a line than the board (a board of
// another size, or another board), or one whose squares are large for this
// scale and whose next corners beyond each side would still be well inside
// the image (a whole board of another size, or a board whose outer corners
// are occluded). Otherwise (holes, squares small against the kernel, or a
// grid cut by the image border) another scale may find the rest.
Failure GridFailure(const Grid& g, const std::vector<Candidate>& cands, const CheckerboardSpec& board, int w, int h,
                    double border, double circle) {
  int a0 = 1 << 30, a1 = -(1 << 30), c0 = 1 << 30, c1 = -(1 << 30);
  for (const auto& [cell, idx] : g.cells) {
    a0 = std::min(a0, cell.first), a1 = std::max(a1, cell.first);
    c0 = std::min(c0, cell.second), c1 = std::max(c1, cell.second);
  }
  const int da = a1 - a0 + 1, dc = c1 - c0 + 1;
  if (int(g.cells.size()) != da * dc) return Failure::kIncompleteGrid;  // holes
  const bool fits = (da <= board.rows && dc <= board.cols) || (da <= board.cols && dc <= board.rows);
  if (!fits) return Failure::kGridNotTheBoard;
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

}  // namespace

void CornerDetectionOptions::Check() const {
  Require(std::isfinite(sigma_px) && sigma_px >= 0.7 && sigma_px <= 5, "sigma_px",
          "must be in [0.7, 5] pixels, got " + FormatNumber(sigma_px));
  Require(min_response > 0 && min_response < 1, "min_response", "must be in (0, 1), got " + FormatNumber(min_response));
  Require(neighbour_tolerance > 0 && neighbour_tolerance < 0.5, "neighbour_tolerance",
          "must be in (0, 0.5), got " + FormatNumber(neighbour_tolerance));
  Require(max_seeds >= 1, "max_seeds", "must be >= 1, got " + std::to_string(max_seeds));
}

namespace {

struct ScaleResult {
  CornerDetection det;
  Failure failure = Failure::kNone;
};

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
  {
    std::vector<float> values;
    const size_t step = std::max<size_t>(1, sm.r.size() / 1000000);
    for (size_t k = 0; k < sm.r.size(); k += step) values.push_back(sm.r[k]);
    det.contrast = Percentile(values, 0.999) - Percentile(values, 0.001);
  }
  if (!(det.contrast > 5 * noise) || !(det.contrast > 0)) {
    return refuse(Failure::kNoContrast, "no checkerboard found: the image has no contrast above its noise (contrast " + Fmt(det.contrast) +
                  ", noise " + Fmt(noise) + ")");
  }

  // ---- saddle candidates
  // Each corner is judged against its own contrast (the range of the smoothed
  // image on the validation circle), so that uneven light and vignetting do
  // not matter. That range must exceed 3 noise σ, and a tenth of the image's
  // contrast (the noise estimate misses noise that the camera has smoothed,
  // e.g. by JPEG compression, and faint texture is no board).
  const double min_range = std::max(3 * noise, 0.1 * det.contrast);
  const double sigma_eff2 = sigma * sigma + 1.0 / 6.0;  // Gaussian, the kernel's pixel box and the pixel's own
  const double circle = 2.5 * sigma + 1;                 // validation circle radius
  auto response_floor = [&](double range) { return std::pow(options.min_response * range / (M_PI * sigma_eff2), 2); };
  const double threshold = response_floor(min_range);
  const double border = 2 * sigma + 2;
  const int nms = std::max(1, int(std::lround(sigma)));
  std::vector<float> strength(size_t(w) * size_t(h), 0.0f);
  for (size_t k = 0; k < strength.size(); ++k) {
    strength[k] = sm.rxy[k] * sm.rxy[k] - sm.rxx[k] * sm.ryy[k];
  }
  std::vector<Candidate> cands;
  const int b0 = int(std::ceil(border));
  for (int y = b0; y < h - b0; ++y) {
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
      if (!(range >= min_range) || !(s > response_floor(range))) continue;
      if (!RefineSaddle(iv, sigma, kernels.radius, border, &c.p, &c.hessian)) continue;
      if (!EdgeDirections(sm, c.p, circle, min_range, &c)) continue;
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
    if (g.cells.size() > best.cells.size()) best = g;
    int a0 = 1 << 30, a1 = -(1 << 30), c0 = 1 << 30, c1 = -(1 << 30);
    for (const auto& [cell, idx] : g.cells) {
      a0 = std::min(a0, cell.first), a1 = std::max(a1, cell.first);
      c0 = std::min(c0, cell.second), c1 = std::max(c1, cell.second);
    }
    const int da = a1 - a0 + 1, dc = c1 - c0 + 1;
    const bool full = int(g.cells.size()) == da * dc;
    if (full && ((da == board.rows && dc == board.cols) || (da == board.cols && dc == board.rows))) {
      best = g;
      complete = true;
      ni = da, amin = a0, bmin = c0;
      break;
    }
  }
  for (const auto& [cell, idx] : best.cells) det.grid.push_back({cands[size_t(idx)].p, cell.first, cell.second});
  if (!complete) {
    if (best.cells.size() < 4) return refuse(Failure::kNoGrid, "no checkerboard found: no grid of corners");
    return refuse(GridFailure(best, cands, board, w, h, border, circle), "found a grid of " + std::to_string(best.cells.size()) + " corners, not the complete " +
                  std::to_string(board.rows) + " x " + std::to_string(board.cols) +
                  " board: the board is partly outside the image, occluded, or too small or blurred for sigma_px = " +
                  Fmt(sigma));
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
        if (even_minus_odd < -min_range) ++even_darker;
        if (even_minus_odd > min_range) ++odd_darker;
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
  double kg = 0, k0 = 0;
  for (float v : kernels.k1) kg += double(v) * v;
  for (float v : kernels.k0) k0 += double(v) * v;
  const double gradient_var = noise * noise * kg * k0;
  det.grid.clear();
  for (int i = 0; i < R; ++i) {
    for (int j = 0; j < C; ++j) {
      const Candidate& c = at(i, j);
      det.corners.push_back(c.p);
      const Eigen::Matrix2d hinv = c.hessian.inverse();
      det.corner_std_px.push_back(std::sqrt(gradient_var * (hinv * hinv.transpose()).trace() / 2));
      det.grid.push_back({c.p, i, j});
    }
  }
  det.ok = true;
  return out;
}

// Scales to try after the requested one failed for a reason another scale
// may cure: twice and three times it (blur, large squares), then 1/1.5 and
// 1/2.25 of it (small or foreshortened squares), within [0.7, 5]; values
// within 10% of one already on the ladder are left out.
std::vector<double> ScaleLadder(double sigma) {
  std::vector<double> ladder{sigma};
  for (double f : {2.0, 3.0, 1 / 1.5, 1 / 2.25}) {
    const double s = std::clamp(sigma * f, 0.7, 5.0);
    bool near = false;
    for (double o : ladder) near = near || std::abs(s - o) < 0.1 * o;
    if (!near) ladder.push_back(s);
  }
  ladder.erase(ladder.begin());
  return ladder;
}

}  // namespace

template <typename T>
CornerDetection DetectCheckerboard(const ImageView<T>& view, const CheckerboardSpec& board,
                                   const CornerDetectionOptions& options) {
  options.Check();
  board.Check();
  if (view.empty() || view.data == nullptr || view.channels < 1) throw InputError("", "empty image");
  const Image<float> img = ToFloat(view);
  double noise = NoiseSigma(img);
  if (std::is_integral_v<T>) noise = std::sqrt(noise * noise + 1.0 / 12.0);  // quantisation
  ScaleResult first = DetectAtScale(img, noise, board, options, options.sigma_px);
  if (first.det.ok || !options.other_scales ||
      !(first.failure == Failure::kFewCandidates || first.failure == Failure::kNoGrid ||
        first.failure == Failure::kIncompleteGrid)) {
    return std::move(first.det);
  }
  // Another scale: the first complete grid whose order the colours confirm.
  std::string tried;
  for (double s : ScaleLadder(options.sigma_px)) {
    ScaleResult r = DetectAtScale(img, noise, board, options, s);
    ++first.det.other_scales_tried;
    // A larger kernel averages more of the corner's surroundings: where an
    // occluder hides a corner it can still make a saddle there, a pixel or
    // two off. A corner found at a larger scale must therefore be
    // point-symmetric within that scale's validation circle (an occluder
    // beside it is not) and a saddle at the requested scale too, at the
    // same place. (A smaller kernel sees less than the requested one: it
    // cannot make corners out of an occluder's surroundings.)
    // Any other scale: each corner where the homography through its
    // neighbours puts it, and a saddle about as sharp as theirs (a corner
    // made of an occluder's edges is off, and weak: its predicted standard
    // deviation at most twice the median of its neighbours').
    for (int i = 0; r.det.ok && i < board.rows; ++i) {
      for (int j = 0; r.det.ok && j < board.cols; ++j) {
        const double std_px = r.det.corner_std_px[size_t(i * board.cols + j)];
        std::vector<double> around;
        for (int a = std::max(0, i - 1); a <= std::min(board.rows - 1, i + 1); ++a)
          for (int b = std::max(0, j - 1); b <= std::min(board.cols - 1, j + 1); ++b)
            if (a != i || b != j) around.push_back(r.det.corner_std_px[size_t(a * board.cols + b)]);
        std::nth_element(around.begin(), around.begin() + ptrdiff_t(around.size() / 2), around.end());
        if (!(std_px <= 2 * around[around.size() / 2])) r.det.ok = false;
        if (!(OffGrid(r.det.corners, board.rows, board.cols, i, j) <= 0.35 + 6 * std_px)) r.det.ok = false;
      }
    }
    if (r.det.ok && s > options.sigma_px) {
      const double min_range = std::max(3 * noise, 0.1 * first.det.contrast);
      for (size_t k = 0; r.det.ok && k < r.det.corners.size(); ++k) {
        if (!(PointAsymmetry(img, r.det.corners[k], 2.5 * s + 1, noise) <= kMaxAsymmetry) ||
            !SaddleAtScale(img.View(), r.det.corners[k], r.det.corner_std_px[k], options.sigma_px, s, noise, min_range,
                           options.min_response)) {
          r.det.ok = false;
        }
      }
    }
    if (r.det.ok) {
      r.det.other_scales_tried = first.det.other_scales_tried;
      return std::move(r.det);
    }
    tried += (tried.empty() ? "" : ", ") + Fmt(s);
  }
  first.det.reason += " (also refused at sigma_px = " + tried + ")";
  return std::move(first.det);
}

template CornerDetection DetectCheckerboard<uint8_t>(const ImageView<uint8_t>&, const CheckerboardSpec&,
                                                     const CornerDetectionOptions&);
template CornerDetection DetectCheckerboard<uint16_t>(const ImageView<uint16_t>&, const CheckerboardSpec&,
                                                      const CornerDetectionOptions&);
template CornerDetection DetectCheckerboard<float>(const ImageView<float>&, const CheckerboardSpec&,
                                                   const CornerDetectionOptions&);

CornerDetection DetectCheckerboard(const AnyImage& image, const CheckerboardSpec& board,
                                   const CornerDetectionOptions& options) {
  return std::visit([&](const auto& img) { return DetectCheckerboard(img.View(), board, options); }, image);
}

}  // namespace lt

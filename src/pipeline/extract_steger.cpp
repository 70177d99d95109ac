// Steger's method (C. Steger, "An unbiased detector of curvilinear
// structures", IEEE PAMI 20(2), 1998) for bright stripes, organised for speed:
//  1. a cheap pass marks columns holding pixels of at least half the threshold,
//     per band of rows; Gaussian derivatives are computed (separably) only in
//     those column intervals, widened by the kernel support;
//  2. at each such pixel the Hessian's most negative eigenvalue gives the
//     normal n and the second derivative along it; the Taylor step
//     t = -(grad . n) / (n^T H n) gives the subpixel line point, kept when it
//     lies in the pixel (with a small margin) and the second derivative passes
//     the low threshold;
//  3. hysteresis: 8-connected line pixels form chains, kept when one of their
//     points passes the high threshold;
//  4. one point per search row and chain (nearest to the row) is refined by
//     Newton steps along the normal with derivatives evaluated at the exact
//     subpixel position, removing the bias of the single Taylor step; the
//     output is where the refined line crosses the row. Points near line ends
//     (intensity changing along the line) are dropped, and rows within
//     3 sigma of the top and bottom give no points (mirrored borders would bend
//     tilted stripes).
#include "pipeline/extract_steger.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace lt {

namespace {

constexpr double kFwhmPerSigma = 2.3548200450309493;  // 2 sqrt(2 ln 2)
constexpr double kPixelVariance = 1.0 / 12.0;          // variance of a pixel-wide box
constexpr float kInPixelMargin = 0.6f;                 // accept |t n| <= 0.6 (Steger: 0.5)
constexpr int kColumnDilation = 2;                     // columns around candidate pixels
constexpr double kMaxCurvatureRatio = 0.3;             // |curvature along| / |curvature across|
constexpr double kMaxAlongGradient = 0.5;              // |dr/dt| S / r, see Refine
constexpr double kFinalStep = 0.05;                    // last Newton step (pixels)

// Most negative eigenvalue of [[a, b], [b, c]] and its unit eigenvector; also
// returns the other eigenvalue.
inline void MinEigen(double a, double b, double c, double* lambda, double* other, double* nx, double* ny) {
  const double mean = 0.5 * (a + c), diff = 0.5 * (a - c);
  const double root = std::sqrt(diff * diff + b * b);
  *lambda = mean - root;
  *other = mean + root;
  // (b, lambda - a) and (lambda - c, b) are both eigenvectors; use the longer.
  double ux = b, uy = *lambda - a;
  double vx = *lambda - c, vy = b;
  if (ux * ux + uy * uy < vx * vx + vy * vy) ux = vx, uy = vy;
  double len = std::sqrt(ux * ux + uy * uy);
  if (len == 0) {  // isotropic: any direction; take x
    *nx = 1, *ny = 0;
    return;
  }
  *nx = ux / len, *ny = uy / len;
}

template <typename T>
T CandidateLevel(double level) {
  if constexpr (std::is_integral_v<T>) {
    double c = std::ceil(level);
    return T(std::clamp(c, 0.0, double(std::numeric_limits<T>::max())));
  } else {
    return T(level);
  }
}

}  // namespace

StegerDetector::StegerDetector(const ExtractionOptions& options) : kernels_(options.SigmaUsed()) {
  Configure(options);
}

void StegerDetector::Configure(const ExtractionOptions& options) {
  options_ = options;
  if (kernels_.sigma != options.SigmaUsed()) kernels_ = GaussianKernels(options.SigmaUsed());
  const double s = options.expected_width / kFwhmPerSigma;
  const double sigma = kernels_.sigma;
  const double S = std::sqrt(s * s + sigma * sigma + 2 * kPixelVariance);
  contrast_per_curvature_ = S * S * S / s;
  row_margin_ = options.EdgeLinesWithoutPoints();
  min_abs_nx_ = std::cos(options.max_angle_deg * M_PI / 180.0);
}

template <typename T>
void StegerDetector::DetectBand(const ImageView<T>& image, int y0, int y1, double candidate_level, double low_curv,
                                std::vector<Candidate>* out) {
  const int W = image.width, H = image.height, R = kernels_.radius;
  Scratch& s = scratch_.local();
  // 1. Columns that may hold a stripe near rows [y0, y1).
  s.colmark.assign(W, 0);
  const T level = CandidateLevel<T>(candidate_level);
  if (candidate_level > double(std::numeric_limits<T>::max())) return;
  uint8_t* mark = s.colmark.data();
  for (int y = std::max(0, y0 - 1); y < std::min(H, y1 + 1); ++y) {
    const T* row = image.Row(y);
#pragma omp simd
    for (int x = 0; x < W; ++x) mark[x] |= uint8_t(row[x] >= level);
  }
  s.intervals.clear();
  const int lo = R, hi = W - R;  // line points need the kernel support inside the image
  for (int x = 0; x < W;) {
    if (!mark[x]) {
      ++x;
      continue;
    }
    int e = x;
    while (e < W && mark[e]) ++e;
    int a = std::max(lo, x - kColumnDilation), b = std::min(hi, e + kColumnDilation);
    if (a < b) {
      if (!s.intervals.empty() && a <= s.intervals.back()) {
        s.intervals.back() = std::max(s.intervals.back(), b);
      } else {
        s.intervals.push_back(a);
        s.intervals.push_back(b);
      }
    }
    x = e;
  }
  // 2. Derivatives in each interval, then line points.
  const int rows = (y1 - y0) + 2 * R;
  const double margin = kInPixelMargin;
  for (size_t iv = 0; iv < s.intervals.size(); iv += 2) {
    const int a = s.intervals[iv], b = s.intervals[iv + 1], len = b - a;
    const size_t need = size_t(rows) * len;
    if (s.h0.size() < need) s.h0.resize(need), s.h1.resize(need), s.h2.resize(need);
    if (s.line.size() < size_t(len + 2 * R)) s.line.resize(len + 2 * R);
    if (s.rx.size() < size_t(len)) {
      for (auto* v : {&s.rx, &s.ry, &s.rxx, &s.rxy, &s.ryy}) v->resize(len);
    }
    float* line = s.line.data();
    for (int k = 0; k < rows; ++k) {
      const T* row = image.Row(MirrorIndex(y0 - R + k, H));
      if (a - R >= 0 && b + R <= W) {
        const T* src = row + (a - R);
        for (int i = 0; i < len + 2 * R; ++i) line[i] = float(src[i]);
      } else {
        for (int i = 0; i < len + 2 * R; ++i) line[i] = float(row[MirrorIndex(a - R + i, W)]);
      }
      ConvolveSegment3(line, len, kernels_, &s.h0[size_t(k) * len], &s.h1[size_t(k) * len], &s.h2[size_t(k) * len]);
    }
    const float* k0 = kernels_.k0.data();
    const float* k1 = kernels_.k1.data();
    const float* k2 = kernels_.k2.data();
    for (int y = std::max(y0, row_margin_); y < std::min(y1, H - row_margin_); ++y) {
      float* __restrict rx = s.rx.data();
      float* __restrict ry = s.ry.data();
      float* __restrict rxx = s.rxx.data();
      float* __restrict rxy = s.rxy.data();
      float* __restrict ryy = s.ryy.data();
      for (int x = 0; x < len; ++x) rx[x] = ry[x] = rxx[x] = rxy[x] = ryy[x] = 0;
      for (int j = 0; j <= 2 * R; ++j) {
        const size_t off = size_t(y - y0 + 2 * R - j) * len;  // h row of image row y - (j - R)
        const float* __restrict g0 = &s.h0[off];
        const float* __restrict g1 = &s.h1[off];
        const float* __restrict g2 = &s.h2[off];
        const float c0 = k0[j], c1 = k1[j], c2 = k2[j];
        for (int x = 0; x < len; ++x) {
          rx[x] += c0 * g1[x];
          rxx[x] += c0 * g2[x];
          ry[x] += c1 * g0[x];
          rxy[x] += c1 * g1[x];
          ryy[x] += c2 * g0[x];
        }
      }
      for (int x = 0; x < len; ++x) {
        // Cheap rejection: a bright line needs rxx + ryy clearly negative.
        if (!(rxx[x] + ryy[x] < -low_curv)) continue;
        double lambda, other, nx, ny;
        MinEigen(rxx[x], rxy[x], ryy[x], &lambda, &other, &nx, &ny);
        if (!(-lambda >= low_curv) || -lambda < std::abs(other)) continue;
        const double t = -(rx[x] * nx + ry[x] * ny) / lambda;
        const double ox = t * nx, oy = t * ny;
        if (std::abs(ox) > margin || std::abs(oy) > margin) continue;
        out->push_back({a + x, y, float(a + x + ox), float(y + oy), float(nx), float(ny), float(-lambda)});
      }
    }
  }
  std::sort(out->begin(), out->end(), [](const Candidate& p, const Candidate& q) {
    return p.y != q.y ? p.y < q.y : p.x < q.x;
  });
}

namespace {
int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}
}  // namespace

void StegerDetector::LinkAndSelect(double high_curv) {
  // 8-connected chains of line pixels (candidates are sorted by row, then column).
  const int n = int(candidates_.size());
  parent_.resize(n);
  for (int i = 0; i < n; ++i) parent_[i] = i;
  int prev_begin = 0, prev_end = 0;  // candidates of row y - 1
  for (int i = 0; i < n;) {
    const int y = candidates_[i].y;
    int e = i;
    while (e < n && candidates_[e].y == y) ++e;
    if (prev_end > prev_begin && candidates_[prev_begin].y != y - 1) prev_begin = prev_end;  // gap in rows
    int p = prev_begin;
    for (int k = i; k < e; ++k) {
      const int x = candidates_[k].x;
      if (k > i && candidates_[k - 1].x >= x - 1) parent_[Find(parent_, k)] = Find(parent_, k - 1);
      while (p < prev_end && candidates_[p].x < x - 1) ++p;
      for (int q = p; q < prev_end && candidates_[q].x <= x + 1; ++q) {
        int ra = Find(parent_, k), rb = Find(parent_, q);
        if (ra != rb) parent_[ra] = rb;
      }
    }
    prev_begin = i;
    prev_end = e;
    i = e;
  }
  component_max_.assign(n, 0.0f);
  for (int i = 0; i < n; ++i) {
    int r = Find(parent_, i);
    component_max_[r] = std::max(component_max_[r], candidates_[i].response);
  }
  // Per row: clusters of adjacent pixels of one kept chain; the point nearest
  // the row represents the cluster.
  selected_.clear();
  for (int i = 0; i < n;) {
    const int y = candidates_[i].y;
    int e = i;
    while (e < n && candidates_[e].y == y) ++e;
    for (int k = i; k < e;) {
      const int root = Find(parent_, k);
      int best = k;
      int m = k + 1;
      while (m < e && candidates_[m].x <= candidates_[m - 1].x + 1 && Find(parent_, m) == root) {
        if (std::abs(candidates_[m].py - y) < std::abs(candidates_[best].py - y)) best = m;
        ++m;
      }
      if (component_max_[root] >= high_curv && std::abs(candidates_[best].nx) >= min_abs_nx_) selected_.push_back(best);
      k = m;
    }
    i = e;
  }
}

template <typename T>
bool StegerDetector::Refine(const ImageView<T>& image, const Candidate& c, StripePoint* point) const {
  const double sigma = kernels_.sigma;
  const int R = kernels_.radius;
  double px = c.px, py = c.py, nx = c.nx, ny = c.ny;
  double lambda = 0, r = 0, step = 1, grad_along = 0;
  // Newton converges cubically on a symmetric ridge: after a step below
  // kFinalStep the remaining error is ~ step^3 / S^2 < 1e-4 px.
  for (int iter = 0; iter < 4 && std::abs(step) > kFinalStep; ++iter) {
    SmoothedDerivatives d = SmoothedDerivativesAt(image, px, py, sigma, R);
    double other;
    MinEigen(d.rxx, d.rxy, d.ryy, &lambda, &other, &nx, &ny);
    if (!(lambda < 0)) return false;
    // Along a line the curvature is small; near a line's end (or on a blob)
    // it approaches the curvature across, and the normal is unreliable.
    if (other < kMaxCurvatureRatio * lambda) return false;
    step = -(d.rx * nx + d.ry * ny) / lambda;
    if (!(std::abs(step) <= 1.0)) return false;
    r = d.r;
    grad_along = -d.rx * ny + d.ry * nx;
    px += step * nx;
    py += step * ny;
  }
  if (!(std::abs(step) <= kFinalStep)) return false;
  const int W = image.width;
  if (px < R || px > W - 1 - R) return false;  // kernel support would leave the image
  if (std::abs(nx) < min_abs_nx_) return false;
  const double y = c.y;
  if (std::abs(py - y) > kInPixelMargin + 0.05) return false;
  // Line ends: the intensity changes along the line. With the smoothed
  // profile's width S = sqrt(r / -lambda), a Gaussian stripe of constant
  // intensity has |dr/dt| S / r = 0; within about a filter sigma of an end it
  // exceeds 0.5 and the centre is biased, so such points are dropped.
  const double level = r - options_.background;
  if (!(level > 0)) return false;
  if (std::abs(grad_along) * std::sqrt(level / -lambda) > kMaxAlongGradient * level) return false;
  // Where the line (direction (-ny, nx)) crosses row y.
  const double u = px - (y - py) * ny / nx;
  const double S2 = level / -lambda;
  const double s2 = S2 - sigma * sigma - 2 * kPixelVariance;
  point->u = u;
  point->v = y;
  point->width = kFwhmPerSigma * std::sqrt(std::max(0.0, s2));
  point->strength = -lambda * contrast_per_curvature_;
  point->plane = -1;
  return std::isfinite(u) && std::isfinite(point->width) && std::isfinite(point->strength);
}

template <typename T>
void StegerDetector::Run(const ImageView<T>& image, const MethodParams& params, std::vector<StripePoint>* out) {
  const double low_curv = params.threshold / contrast_per_curvature_;
  const double high_curv = params.high_threshold / contrast_per_curvature_;
  const double candidate_level = 0.5 * params.threshold;
  constexpr int kBandRows = 16;
  const int bands = (image.height + kBandRows - 1) / kBandRows;
  if (int(band_candidates_.size()) < bands) band_candidates_.resize(bands);
  ForEachBand(image.height, kBandRows, [&](int band, int y0, int y1) {
    band_candidates_[band].clear();
    DetectBand(image, y0, y1, candidate_level, low_curv, &band_candidates_[band]);
  });
  candidates_.clear();
  for (int b = 0; b < bands; ++b) candidates_.insert(candidates_.end(), band_candidates_[b].begin(), band_candidates_[b].end());
  LinkAndSelect(high_curv);
  const int n = int(selected_.size());
  refined_.resize(n);
  refined_ok_.resize(n);
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 64), [&](const tbb::blocked_range<int>& range) {
    for (int i = range.begin(); i < range.end(); ++i) {
      refined_ok_[i] = Refine(image, candidates_[selected_[i]], &refined_[i]);
    }
  });
  // Clusters of one chain in a row that refine to the same crossing give one point.
  const size_t first = out->size();
  for (int i = 0; i < n; ++i) {
    if (!refined_ok_[i]) continue;
    const StripePoint& p = refined_[i];
    bool duplicate = false;
    for (size_t k = out->size(); k > first && (*out)[k - 1].v == p.v; --k) {
      if (std::abs((*out)[k - 1].u - p.u) < 0.5) duplicate = true;
    }
    if (!duplicate) out->push_back(p);
  }
}

template void StegerDetector::Run<uint8_t>(const ImageView<uint8_t>&, const MethodParams&, std::vector<StripePoint>*);
template void StegerDetector::Run<uint16_t>(const ImageView<uint16_t>&, const MethodParams&, std::vector<StripePoint>*);
template void StegerDetector::Run<float>(const ImageView<float>&, const MethodParams&, std::vector<StripePoint>*);

}  // namespace lt

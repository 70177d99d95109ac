// Checkerboard corner detection's candidate corners and their tests
// (pipeline/calib_corner_candidates.h): noise, smoothing, saddle refinement,
// edge directions, the saddle at a finer scale, point asymmetry.
#include "pipeline/calib_corner_candidates.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "pipeline/gaussian_filter.h"

namespace lt {
namespace corner_detail {

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

Smoothed Smooth(const Image<float>& img, const GaussianKernels& k) {
  Smoothed s;
  s.w = img.width, s.h = img.height;
  const int w = s.w, h = s.h, R = k.radius;
  const size_t n = size_t(w) * size_t(h);
  std::vector<float> h0(n), h1(n), h2(n);
  // Rows in parallel: each output row is computed alone, in a fixed order, so
  // the result does not depend on the threads.
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& rows) {
    std::vector<float> row(size_t(w + 2 * R));
    for (int y = rows.begin(); y < rows.end(); ++y) {
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
  });
  s.r.assign(n, 0);
  s.strength.assign(n, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& rows) {
    // The second derivatives of one row at a time: only the response is kept
    // (a 12 MP image's three planes of them were 144 MB).
    const size_t row_len = size_t(w);
    std::vector<float> row_xx(row_len), row_xy(row_len), row_yy(row_len);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      float* r = &s.r[size_t(y) * size_t(w)];
      float* rxx = row_xx.data();
      float* rxy = row_xy.data();
      float* ryy = row_yy.data();
      std::fill(row_xx.begin(), row_xx.end(), 0.0f);
      std::fill(row_xy.begin(), row_xy.end(), 0.0f);
      std::fill(row_yy.begin(), row_yy.end(), 0.0f);
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
      float* strength = &s.strength[size_t(y) * size_t(w)];
      for (int x = 0; x < w; ++x) strength[x] = rxy[x] * rxy[x] - rxx[x] * ryy[x];
    }
  });
  return s;
}

// Newton's method on the gradient of the smoothed image: the saddle point.
double SaddleStdPx(const GaussianKernels& kernels, double noise, const Eigen::Matrix2d& hessian) {
  double kg = 0, k0 = 0;
  for (float v : kernels.k1) kg += double(v) * v;
  for (float v : kernels.k0) k0 += double(v) * v;
  const Eigen::Matrix2d hinv = hessian.inverse();
  return std::sqrt(noise * noise * kg * k0 * (hinv * hinv.transpose()).trace() / 2);
}

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

// The smoothed image on a circle around p; returns its range (max − min).
namespace {

// The directions of the kCircleSamples samples on a validation circle,
// counter-clockwise from +x: computed once (the candidate search samples a
// circle at every local maximum of the response, millions in a 12 MP photo,
// where the cos and sin took a fifth of the detection's time).
struct UnitCircle {
  double c[kCircleSamples], s[kCircleSamples];
  UnitCircle() {
    for (int k = 0; k < kCircleSamples; ++k) {
      const double a = 2 * M_PI * k / kCircleSamples;
      c[k] = std::cos(a), s[k] = std::sin(a);
    }
  }
};
const UnitCircle kUnitCircle;

}  // namespace

double CircleSamples(const Smoothed& s, const Eigen::Vector2d& p, double radius, double* v) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int k = 0; k < kCircleSamples; ++k) {
    v[k] = s.Sample(p.x() + radius * kUnitCircle.c[k], p.y() + radius * kUnitCircle.s[k]);
    lo = std::min(lo, v[k]);
    hi = std::max(hi, v[k]);
  }
  return hi - lo;
}

namespace {

// The edges from the smoothed image sampled on the circle (kCircleSamples
// values, counter-clockwise from +x).
bool EdgeDirectionsOnRing(const double* v, const ContrastFloor& floor, Candidate* c) {
  constexpr int kSamples = kCircleSamples;
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int k = 0; k < kSamples; ++k) lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
  if (!(hi - lo >= floor.For(hi))) return false;
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

}  // namespace

bool EdgeDirections(const Smoothed& s, const Eigen::Vector2d& p, double radius, const ContrastFloor& floor, Candidate* c) {
  double v[kCircleSamples];
  CircleSamples(s, p, radius, v);
  return EdgeDirectionsOnRing(v, floor, c);
}

namespace {

// Whether the saddle at q (its Hessian at scale `sigma`) responds with at
// least min_response of the ideal for the range of the smoothed image on the
// validation circle of `sigma` around q, at scale `ideal_sigma`, and the
// circle shows the X of step 3.
bool ValidSaddleAt(const ImageView<float>& img, const Eigen::Vector2d& q, const Eigen::Matrix2d& hessian, double sigma,
                   double ideal_sigma, const ContrastFloor& floor, double min_response) {
  const GaussianKernels kernels(sigma);
  const double circle = 2.5 * sigma + 1;
  double v[kCircleSamples], lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int k = 0; k < kCircleSamples; ++k) {
    v[k] = SmoothedDerivativesAt(img, q.x() + circle * kUnitCircle.c[k], q.y() + circle * kUnitCircle.s[k], sigma,
                                 kernels.radius).r;
    lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
  }
  const double ideal = (hi - lo) / (M_PI * (ideal_sigma * ideal_sigma + 1.0 / 6.0));
  if (!(std::sqrt(std::max(0.0, -hessian.determinant())) >= min_response * ideal)) return false;
  Candidate c;
  return EdgeDirectionsOnRing(v, floor, &c);
}

}  // namespace

bool SaddleNear(const ImageView<float>& img, const Eigen::Vector2d& start, double sigma, const ContrastFloor& floor,
                double min_response, Eigen::Vector2d* p, Eigen::Matrix2d* hessian) {
  const GaussianKernels kernels(sigma);
  *p = start;
  if (!RefineSaddle(img, sigma, kernels.radius, 2 * sigma + 2, p, hessian)) return false;
  return ValidSaddleAt(img, *p, *hessian, sigma, sigma, floor, min_response);
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
                   double noise, const ContrastFloor& floor, double min_response) {
  const GaussianKernels kernels(sigma);
  Eigen::Vector2d q = p;
  Eigen::Matrix2d hessian;
  if (!RefineSaddle(img, sigma, kernels.radius, 2 * sigma + 2, &q, &hessian)) return false;
  // The two saddles differ by the noise (the predicted standard deviations
  // of both) and by a few hundredths of a pixel of model error.
  const double q_std = SaddleStdPx(kernels, noise, hessian);
  const double tol = 0.05 + 4 * std::sqrt(q_std * q_std + p_std * p_std);
  if (!((q - p).norm() <= tol)) return false;
  return ValidSaddleAt(img, q, hessian, sigma, found_sigma, floor, min_response);
}

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

}  // namespace corner_detail
}  // namespace lt

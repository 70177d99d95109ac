// The centroid of the centre-of-mass extractor (extract_com.cpp), for callers
// that choose where the window starts (e.g. a benchmark that compares a render
// with a reference column by column, starting from the reference's centre).
//
// WindowCentroid: the centroid of max(0, line[x] - base) over [c - h, c + h],
// each pixel x (covering [x - 0.5, x + 0.5]) weighted by the fraction of it
// inside the window. SelfCentredCentroid: the window centred on the centroid
// itself, iterated from `start` until it moves by less than 1e-4 px (at most 8
// times). Both return false when the window leaves the line or holds no light.
#pragma once

#include <algorithm>
#include <cmath>

namespace lt {

// Half width h of the window: `window` px when set (> 0), else 1.25 FWHM (at
// least 1 px), plus half a pixel and half the maximum's plateau of
// `plateau_pixels`, so that h = window + 0.5 spans the pixels window either side.
inline double ComHalfWindow(double fwhm, int plateau_pixels, int window) {
  const double half = window > 0 ? double(window) : std::max(1.0, 1.25 * fwhm);
  return half + 0.5 + 0.5 * (plateau_pixels - 1);
}

template <typename T>
bool WindowCentroid(const T* line, int n, double c, double h, double base, double* centroid) {
  const double lo = c - h, hi = c + h;
  if (!(lo >= -0.5 && hi <= n - 0.5)) return false;
  const int a = int(std::floor(lo + 0.5)), b = std::min(n - 1, int(std::ceil(hi - 0.5)));
  double sw = 0, swx = 0;
  for (int x = a; x <= b; ++x) {
    const double inside = std::min(x + 0.5, hi) - std::max(x - 0.5, lo);
    if (!(inside > 0)) continue;
    const double w = inside * std::max(0.0, double(line[x]) - base);
    sw += w;
    swx += w * x;
  }
  if (!(sw > 0)) return false;
  *centroid = swx / sw;
  return true;
}

// `lo_bound`, `hi_bound`: the window shrinks (symmetrically about c) so as not
// to pass them, e.g. the valleys to neighbouring peaks (ValleyBounds).
template <typename T>
bool SelfCentredCentroid(const T* line, int n, double start, double h, double base, double* centre,
                         double lo_bound = -HUGE_VAL, double hi_bound = HUGE_VAL) {
  constexpr double kTolerance = 1e-4;
  constexpr int kMaxIterations = 8;
  double c = start;
  for (int i = 0; i < kMaxIterations; ++i) {
    double next = 0;
    const double hc = std::min({h, c - lo_bound, hi_bound - c});
    if (!(hc > 0.5) || !WindowCentroid(line, n, c, hc, base, &next)) return false;
    const bool settled = std::abs(next - c) < kTolerance;
    c = next;
    if (settled) break;
  }
  *centre = c;
  return true;
}

// Valleys between the peak on plateau [first, last] and neighbouring peaks
// resolved at half height, searched up to `reach` px beyond the plateau: walking
// outwards, once the line has fallen below the half level
// base + (peak - base) / 2 and rises above it again, to over twice the lowest
// level passed (as multicom splits a run), the lowest pixel passed is the
// valley (-HUGE_VAL / HUGE_VAL: none, so the bounds go to SelfCentredCentroid
// as they are). A centroid window around the peak that reaches
// past a valley takes in the neighbour and is pulled towards it (to the
// midpoint for two equal stripes). A neighbour reaching `neighbour_min` (the
// threshold: a peak the extractor would see on its own) counts even when it
// stays under half of this peak: a stripe at 0.3 to 0.5 of the peak 6 to 7 px
// from a sigma-1.5 stripe pulled com's window by 0.2 to 0.6 px (up to 1.3 px
// where it hovered about the half level); a noise ripple in the tail, under the
// threshold, still does not.
template <typename T>
void ValleyBounds(const T* line, int n, int first, int last, double peak, double base, int reach, double* lo,
                  double* hi, double neighbour_min = HUGE_VAL) {
  const double half = base + 0.5 * (peak - base);
  *lo = -HUGE_VAL, *hi = HUGE_VAL;
  for (int dir : {-1, 1}) {
    int x = dir < 0 ? first : last;
    const int end = dir < 0 ? std::max(0, first - reach) : std::min(n - 1, last + reach);
    bool below = false;
    int vmin = x;
    for (x += dir; dir < 0 ? x >= end : x <= end; x += dir) {
      const double v = double(line[x]);
      if (!below) {
        if (v < half) below = true, vmin = x;
        continue;
      }
      if (v < double(line[vmin])) vmin = x;
      // (Twice the valley: not a noise ripple at the crossing.)
      if ((v > half || v >= neighbour_min) && v - base > 2 * (double(line[vmin]) - base)) {
        (dir < 0 ? *lo : *hi) = vmin;
        break;
      }
    }
  }
}

}  // namespace lt

// Local background of a peak on a search line (--background local,
// BackgroundMode::kLocal), for max, com and multicom. Ambient light puts a
// sloped or uneven level under the stripe; one constant level cannot remove it.
//
// Definition. For a peak (a local-maximum plateau [first, last] of the line),
// the background is the straight line B(x) through two flank levels:
//   - the flanks lie just outside com's window around the peak: with
//     h = ComHalfWindow(FWHM, plateau, --window) (1.25 FWHM + 0.5 + half the
//     plateau by default) and p the plateau's centre, x_L = floor(p - h - 1.5)
//     and x_R = ceil(p + h + 1.5), so that the three pixels x - 1, x, x + 1 lie
//     wholly outside [p - h, p + h];
//   - a flank's level is the median of those three pixels (robust against a
//     noise spike or a hot pixel);
//   - a flank whose three pixels would reach the valley to a neighbouring peak
//     resolved at half height (ValleyBounds on the line minus B, searched up to
//     a FWHM beyond the flank) sits at that valley instead, and
//     its level is the valley pixel itself (a median there would take the two
//     peaks' flanks in).
// The FWHM is measured above B and B is measured with the flanks that FWHM
// gives, so the two are iterated from a first guess until the flanks stop
// moving (at most 6 times; 2 or 3 suffice). The first guess measures the FWHM
// above the higher of the lowest levels found walking out from the peak on each
// side (up to kLocalReach px, or to a higher value): too wide on ambient light,
// which puts the first flanks further out, from where the iteration comes in.
//
// A peak that does not rise by the threshold above both flank levels is
// dropped (a noise ripple on a stripe's flat top or edge, whose flanks fall
// inside the stripe). The peak's plateau is then the maximum of the line minus
// B over the span around the line's own maximum where it stays above half of
// that (subtracting B can reorder the ripples of a noisy flat top; a saturated
// plateau stays whole). Its height above B is what the threshold is compared
// with and what is reported as strength, and the method measures on
// r(x) = line(x) - B(x) exactly as it does with a background level of 0: max
// takes the plateau's centre, com its self-centred window, multicom the run of
// r >= threshold around the peak (bounded at the valleys). A peak whose flanks
// would leave the line gives no point. Candidates are the line's local-maximum
// plateaus, so a stripe must be a local maximum of the line itself (its flanks
// steeper than the ambient's slope).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "pipeline/extract_methods.h"
#include "pipeline/window_centroid.h"

namespace lt {

// How far the first guess walks out from a peak (pixels).
constexpr int kLocalReach = 64;

// A peak measured above its local background. r[i] = line(s0 + i) - B(s0 + i)
// for i in [0, r.size()); positions are line indices.
struct LocalPeak {
  int first = 0, last = 0;  // plateau of r's maximum
  double height = 0;        // max of r over the plateau
  double fwhm = 0;          // above B (NaN: not measurable)
  double half_window = 0;   // com's h for this FWHM and plateau
  double valley_lo = -HUGE_VAL, valley_hi = HUGE_VAL;  // valleys to neighbouring peaks (line indices)
  int s0 = 0;
  std::vector<double> r;
};

namespace local_background_detail {

template <typename T>
double Median3(const T* line, int x) {
  double a = double(line[x - 1]), b = double(line[x]), c = double(line[x + 1]);
  return std::max(std::min(a, b), std::min(std::max(a, b), c));
}

// r over [s0, s1] of line - (level_l + slope (x - x_l)).
template <typename T>
void Detrend(const T* line, int s0, int s1, double x_l, double level_l, double slope, LocalPeak* p) {
  p->s0 = s0;
  p->r.resize(size_t(s1 - s0 + 1));
  for (int x = s0; x <= s1; ++x) p->r[size_t(x - s0)] = double(line[x]) - (level_l + slope * (x - x_l));
}

// From the line's plateau [first, last], the plateau of r's maximum over the
// span around it where r stays above half of r's value there (subtracting B
// can reorder noise ripples on a flat top). A maximum on the line's plateau
// keeps the plateau whole (a saturated plateau on a slope stays one peak).
inline void Climb(LocalPeak* p, int first, int last) {
  const std::vector<double>& r = p->r;
  const int n = int(r.size());
  const int a = first - p->s0, b = last - p->s0;
  double m = r[size_t(a)];
  for (int i = a; i <= b; ++i) m = std::max(m, r[size_t(i)]);
  int best = -1;
  double best_value = m;
  for (int dir : {-1, 1}) {
    for (int x = (dir < 0 ? a : b) + dir; x >= 0 && x < n; x += dir) {
      const double v = r[size_t(x)];
      if (v > best_value) best_value = v, best = x;
      if (!(v > 0.5 * best_value)) break;
    }
  }
  if (best < 0) {
    p->first = first;
    p->last = last;
    p->height = m;
    return;
  }
  int lo = best, hi = best;
  while (lo > 0 && r[size_t(lo - 1)] == best_value) --lo;
  while (hi + 1 < n && r[size_t(hi + 1)] == best_value) ++hi;
  p->first = lo + p->s0;
  p->last = hi + p->s0;
  p->height = best_value;
}

}  // namespace local_background_detail

// Measures the peak on line[0, n) whose plateau is [first, last] above its
// local background (definition above). False when it cannot be measured (its
// flanks leave the line, no FWHM) or its height is below `threshold`; the
// width check is the caller's (p->fwhm).
template <typename T>
bool MeasureLocalPeak(const T* line, int n, int first, int last, double threshold, int window, LocalPeak* p) {
  using namespace local_background_detail;
  const double peak = double(line[first]);
  // First guess: the lowest levels walking out on each side.
  double low[2];
  for (int k = 0; k < 2; ++k) {
    const int dir = k == 0 ? -1 : 1;
    int x = dir < 0 ? first : last;
    double m = peak;
    for (int i = 0; i < kLocalReach; ++i) {
      x += dir;
      if (x < 0 || x >= n || double(line[x]) > peak) break;
      m = std::min(m, double(line[x]));
    }
    low[k] = m;
  }
  // The height above B is at most the height above the lower of the two (B at
  // the peak lies between its flank levels).
  if (!(peak - std::min(low[0], low[1]) >= threshold)) return false;
  double base = std::max(low[0], low[1]);
  double fwhm = PeakFwhm(line, n, first, last, peak, base);
  if (std::isnan(fwhm)) return false;
  // Current B: base + slope (x - x_ref).
  double x_ref = first, level_ref = base, slope = 0;
  int pf = first, pl = last;  // current plateau
  int prev_l = -1, prev_r = -1;
  constexpr int kMaxIterations = 6;
  for (int it = 0; it < kMaxIterations; ++it) {
    const double h = ComHalfWindow(fwhm, pl - pf + 1, window);
    const double pc = 0.5 * (pf + pl);
    int xl = int(std::floor(pc - h - 1.5)), xr = int(std::ceil(pc + h + 1.5));
    if (xl - 1 < 0 || xr + 1 > n - 1) return false;  // the flanks leave the line
    // Valleys to neighbouring peaks, on the line minus the current B, searched
    // a FWHM beyond the flanks (to see a neighbour rise above half height).
    const int ext = int(std::ceil(fwhm)) + 2;
    Detrend(line, std::max(0, xl - 1 - ext), std::min(n - 1, xr + 1 + ext), x_ref, level_ref, slope, p);
    Climb(p, pf, pl);
    double vlo = 0, vhi = 0;
    ValleyBounds(p->r.data(), int(p->r.size()), p->first - p->s0, p->last - p->s0, p->height, 0.0,
                 int(p->r.size()), &vlo, &vhi);
    // A valley that the flank's three pixels would reach or pass takes the flank.
    bool at_valley_l = false, at_valley_r = false;
    if (std::isfinite(vlo) && int(vlo) + p->s0 >= xl - 1) xl = int(vlo) + p->s0, at_valley_l = true;
    if (std::isfinite(vhi) && int(vhi) + p->s0 <= xr + 1) xr = int(vhi) + p->s0, at_valley_r = true;
    p->valley_lo = vlo + p->s0;  // infinite (none) stays infinite
    p->valley_hi = vhi + p->s0;
    const double ml = at_valley_l ? double(line[xl]) : Median3(line, xl);
    const double mr = at_valley_r ? double(line[xr]) : Median3(line, xr);
    // The peak must rise by the threshold above both flanks (a noise ripple on
    // a stripe's flat top or edge, whose flanks fall inside the stripe, does not).
    if (!(double(line[pf]) - std::max(ml, mr) >= threshold)) return false;
    x_ref = xl;
    level_ref = ml;
    slope = (mr - ml) / (xr - xl);
    // r with this B over the flanks' span; the peak and its FWHM above it.
    // (reaching a FWHM further, for com's window when the peak's plateau
    // moves or the window centres itself away from the start).
    const int s0 = std::max(0, std::min(xl, int(pc - h - 1.5)) - 1 - ext);
    const int s1 = std::min(n - 1, std::max(xr, int(pc + h + 2.5)) + 1 + ext);
    Detrend(line, s0, s1, x_ref, level_ref, slope, p);
    Climb(p, pf, pl);
    pf = p->first;
    pl = p->last;
    fwhm = PeakFwhm(p->r.data(), int(p->r.size()), pf - p->s0, pl - p->s0, p->height, 0.0);
    p->fwhm = fwhm;
    p->half_window = ComHalfWindow(fwhm, pl - pf + 1, window);
    if (std::isnan(fwhm)) return false;
    if (xl == prev_l && xr == prev_r) break;
    prev_l = xl;
    prev_r = xr;
  }
  return p->height >= threshold;
}

// Local-maximum plateaus [first, last] of line[0, n) (both neighbours lower),
// not touching the line's ends, left to right, whose value is at least
// `min_value`.
template <typename T>
void LocalMaximumPlateaus(const T* line, int n, double min_value, std::vector<LinePeak>* out) {
  out->clear();
  for (int x = 1; x < n - 1;) {
    if (!(line[x] > line[x - 1]) || !(double(line[x]) >= min_value)) {
      ++x;
      continue;
    }
    int last = x;
    while (last + 1 < n && line[last + 1] == line[x]) ++last;
    if (last + 1 < n && line[last + 1] < line[x]) out->push_back({x, last, double(line[x])});
    x = last + 1;
  }
}


// The width check (WidthAccepted) of a peak measured above its local
// background on line y of `lines`: a narrow one must continue on the adjacent
// lines, measured above B at its plateau (the threshold is a height above B).
template <typename T>
bool LocalWidthAccepted(const LocalPeak& p, double threshold, const ExtractionOptions& o, WidthRejections* count,
                        const ImageView<T>& lines, int y) {
  const double value = double(lines.Row(y)[p.first]);
  const double b = value - p.height;
  return WidthAccepted(p.fwhm, o, count, lines, y, LinePeak{p.first, p.last, value}, b, b + threshold);
}

// max and com with the local background: among the local-maximum plateaus of
// line y of `image`, the one with the greatest height above its local
// background that reaches `threshold` and passes the width check (*peak holds
// it and its r). Only the highest candidate's width rejection is counted (one
// per line, as FindRowPeak does).
template <typename T>
bool FindRowPeakLocal(const ImageView<T>& image, int y, double threshold, const ExtractionOptions& o, LocalPeak* peak,
                      WidthRejections* rejected) {
  const T* row = image.Row(y);
  const int n = image.width;
  double row_min = double(row[0]);
  for (int x = 1; x < n; ++x) row_min = std::min(row_min, double(row[x]));
  thread_local std::vector<LinePeak> candidates;
  thread_local LocalPeak trial;
  LocalMaximumPlateaus(row, n, row_min + threshold, &candidates);
  double highest = -HUGE_VAL, best = -HUGE_VAL;
  bool highest_accepted = false;
  WidthRejections highest_rejections;
  for (const LinePeak& c : candidates) {
    if (!MeasureLocalPeak(row, n, c.first, c.last, threshold, o.window, &trial)) continue;
    WidthRejections trial_rejections;
    const bool accepted = trial.height > best && LocalWidthAccepted(trial, threshold, o, &trial_rejections, image, y);
    if (trial.height > highest) {
      highest = trial.height;
      highest_accepted = accepted;
      highest_rejections = trial_rejections;
    }
    if (accepted) {
      best = trial.height;
      std::swap(*peak, trial);
    }
  }
  if (!highest_accepted) *rejected += highest_rejections;  // counts the highest candidate's rejection
  return best > -HUGE_VAL;
}

}  // namespace lt

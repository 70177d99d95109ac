// Narrow peaks: a peak narrower than --min-width along its search line is kept
// only when its light continues on the adjacent search lines (max, com,
// multicom; docs/extraction.md, "Narrow peaks").
//
// Width alone cannot tell a thin stripe (sigma 0.4 px, FWHM about 1.1 px) from
// a hot pixel or a one-pixel noise spike (FWHM 1 px): both are one bright
// pixel between darker ones. What tells them apart is the next search line: a
// stripe, however narrow, crosses it too, within a pixel or so across (a peak
// narrower than 1.5 px along the line belongs to a stripe steeper than about
// 53 degrees from the line, so it moves at most ~1.3 px per line), at about the
// same height; a hot pixel's neighbours there are background. The rule:
//
//   - On an adjacent line, the peak continues when the brightest pixel within
//     one pixel across of the peak's plateau, [first - 1, last + 1], passes
//     the threshold and lies within a factor of 3 of the peak's height above
//     the background (above a third of it, at most three times it): the
//     stripe crosses that line at about the same height. Pixel phase alone
//     varies a thin stripe's peak by up to 2x between lines (its centre on a
//     pixel centre, then between two: an area-sampled Gaussian of sigma 0.3 px
//     gives 0.91 and 0.50 of its amplitude), and noise or speckle on a
//     rendered or real stripe adds to that, hence 3. The threshold keeps noise
//     spikes just above it from chaining through the noise on the next lines;
//     the third keeps a hot pixel on ambient light (whose neighbours pass the
//     threshold) rejected while the ambient is under a third of its height;
//     the upper bound keeps a raw Bayer mosaic of a red or blue laser rejected
//     as before: its green lines' peaks (a quarter of the red height or less)
//     have the bright red pixel right above and below, and its red lines have
//     only green pixels there. The pixels above that level (the threshold, a
//     third) must be one run, on the adjacent line's window and on the peak's
//     own line within 2 px of its plateau: a stripe's cross-section has one
//     peak, while a raw mosaic is a comb, bright pixels either side of a dim
//     one along the line, and its green pixels' quincunx (a green laser, or
//     the green response to a red one) would otherwise chain diagonally.
//   - The light must run through kNarrowPeakMinLines = 3 consecutive lines
//     including the peak's (the chain goes on from the continuing pixels'
//     extent, one pixel wider on each side, line by line): a line inside a
//     stripe continues on both sides, its first and last lines continue on two
//     lines to one side. A single hot pixel, and two hot pixels on adjacent
//     lines (a vertical pair: a cluster defect or a charged particle's short
//     track), are rejected; a shorter piece of stripe than 3 lines is too.
//
// Only narrow peaks are checked, which are rare on frames of ordinary stripes,
// so the cost is a few pixel reads per narrow candidate.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/image.h"

namespace lt {

// Consecutive search lines a narrow peak's light must cross, its own included.
constexpr int kNarrowPeakMinLines = 3;
// The stripe's height on an adjacent line must lie within this factor of the
// peak's height (above the background), either way.
constexpr double kNarrowPeakHeightRatio = 3.0;

namespace narrow_peak_detail {

// Whether line[0, n) continues a peak inside [lo, hi]: the brightest pixel
// there lies in (low, high] and the pixels above `low` there are one run
// [*a, *b] (a stripe's cross-section has one peak; two bright pixels either
// side of a dark one are a Bayer mosaic's green pixels around a red or blue
// one, or two different things).
template <typename T>
bool ContinuationSpan(const T* line, int n, int lo, int hi, double low, double high, int* a, int* b) {
  lo = std::max(lo, 0);
  hi = std::min(hi, n - 1);
  if (lo > hi) return false;
  double brightest = double(line[lo]);
  for (int x = lo + 1; x <= hi; ++x) brightest = std::max(brightest, double(line[x]));
  if (!(brightest > low && brightest <= high)) return false;
  int first = lo;
  while (!(double(line[first]) > low)) ++first;
  int last = hi;
  while (!(double(line[last]) > low)) --last;
  for (int x = first + 1; x < last; ++x) {
    if (!(double(line[x]) > low)) return false;
  }
  *a = first;
  *b = last;
  return true;
}

// How many lines beyond line y in direction dir (-1 or 1), up to `need`, the
// light of [first, last] continues on.
template <typename T>
int ContinuedLines(const ImageView<T>& lines, int y, int dir, int first, int last, double low, double high,
                   int need) {
  int a = first, b = last, count = 0;
  for (int yy = y + dir; count < need && yy >= 0 && yy < lines.height; yy += dir) {
    if (!ContinuationSpan(lines.Row(yy), lines.width, a - 1, b + 1, low, high, &a, &b)) break;
    ++count;
  }
  return count;
}

}  // namespace narrow_peak_detail

// Whether the peak with plateau [first, last] on line y of `lines` (the
// method's working image, whose rows are the search lines), `height` above the
// level `base` its FWHM was measured above, continues through
// kNarrowPeakMinLines lines (above); a continuing pixel must exceed `floor`
// (the value that passes the threshold) as well.
template <typename T>
bool NarrowPeakContinues(const ImageView<T>& lines, int y, int first, int last, double base, double height,
                         double floor) {
  using narrow_peak_detail::ContinuedLines;
  if (!(height > 0)) return false;
  const double low = std::max(floor, base + height / kNarrowPeakHeightRatio);
  const double high = base + height * kNarrowPeakHeightRatio;
  // On its own line, no other bright pixel within 2 px beyond a dim one (a comb).
  int a = 0, b = 0;
  if (!narrow_peak_detail::ContinuationSpan(lines.Row(y), lines.width, first - 2, last + 2, low, HUGE_VAL, &a, &b)) {
    return false;
  }
  const int need = kNarrowPeakMinLines - 1;
  const int up = ContinuedLines(lines, y, -1, first, last, low, high, need);
  if (up >= need) return true;
  return up + ContinuedLines(lines, y, 1, first, last, low, high, need - up) >= need;
}

}  // namespace lt

// Internal interface between StripeExtractor and the per-method files. All
// methods work on a mono image whose rows are the search lines (the extractor
// transposes for column search) and report points in that image's coordinates:
// u along the row, v = row index.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/image.h"
#include "pipeline/extraction_options.h"
#include "pipeline/narrow_peak.h"
#include "pipeline/stripe_point.h"

namespace lt {

// Resolved thresholds for one image type.
struct MethodParams {
  const ExtractionOptions* options = nullptr;
  double threshold = 0;       // minimum peak intensity
  double high_threshold = 0;  // steger hysteresis high threshold
};

// Points gathered per band of rows, so threads write without locking and the
// result order does not depend on scheduling. Buffers keep their capacity.
struct BandedPoints {
  int band_rows = 16;
  std::vector<std::vector<StripePoint>> bands;
  std::vector<WidthRejections> rejected;  // per band

  int Reset(int height) {  // returns the number of bands
    int n = (height + band_rows - 1) / band_rows;
    if (int(bands.size()) < n) bands.resize(n);
    if (int(rejected.size()) < n) rejected.resize(n);
    for (int i = 0; i < n; ++i) {
      bands[i].clear();
      rejected[i] = {};
    }
    used = n;
    return n;
  }
  void AppendTo(std::vector<StripePoint>* out, WidthRejections* rejections) const {
    for (int i = 0; i < used; ++i) {
      out->insert(out->end(), bands[i].begin(), bands[i].end());
      *rejections += rejected[i];
    }
  }
  int used = 0;
};

// Runs fn(band, y0, y1) for every band of rows, in parallel (in the calling
// task arena).
template <typename Fn>
void ForEachBand(int height, int band_rows, Fn&& fn) {
  int n = (height + band_rows - 1) / band_rows;
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 1), [&](const tbb::blocked_range<int>& r) {
    for (int b = r.begin(); b < r.end(); ++b) fn(b, b * band_rows, std::min(height, (b + 1) * band_rows));
  });
}

// A peak on one search line: plateau [first, last] of its maximum value.
struct LinePeak {
  int first = 0;
  int last = 0;
  double value = 0;
};

// Full width at half maximum of the peak around plateau [first, last] of
// line[0, n): the half level is base + (peak - base) / 2, crossings are
// interpolated linearly. Returns NaN when a crossing is not found inside the
// line (the peak runs into the border) or a higher value comes first (the
// "peak" is the flank of another one).
template <typename T>
double PeakFwhm(const T* line, int n, int first, int last, double peak, double base) {
  double half = base + 0.5 * (peak - base);
  int x = first;
  while (x >= 0 && double(line[x]) > half) {
    if (double(line[x]) > peak) return std::nan("");  // the flank of a higher peak
    --x;
  }
  if (x < 0) return std::nan("");
  double a = double(line[x]), b = double(line[x + 1]);
  double left = x + (half - a) / (b - a);
  x = last;
  while (x < n && double(line[x]) > half) {
    if (double(line[x]) > peak) return std::nan("");
    ++x;
  }
  if (x >= n) return std::nan("");
  a = double(line[x - 1]), b = double(line[x]);
  double right = (x - 1) + (a - half) / (a - b);
  return right - left;
}

// Whether a peak passes the width check: its FWHM lies in [min_width,
// max_width] (max_width 0: no upper bound), or it is narrower than min_width
// and its light continues on the adjacent search lines (NarrowPeakContinues:
// a thin stripe, not a hot pixel). `peak` is its plateau on line y of `lines`
// (the method's working image), `base` the level its FWHM was measured above
// and `threshold_level` the value a pixel must reach to pass the threshold
// there (the threshold, or the local background plus the threshold). Counts a
// measured width outside the range (a narrow peak only when it does not
// continue). A NaN width (a peak at the border or on another's flank) is
// rejected and not counted.
template <typename T>
bool WidthAccepted(double fwhm, const ExtractionOptions& o, WidthRejections* count, const ImageView<T>& lines, int y,
                   const LinePeak& peak, double base, double threshold_level) {
  if (fwhm < o.min_width) {
    if (NarrowPeakContinues(lines, y, peak.first, peak.last, base, peak.value - base, threshold_level)) return true;
    ++count->narrow;
    return false;
  }
  if (o.max_width != 0 && fwhm > o.max_width) {
    ++count->wide;
    return false;
  }
  return !std::isnan(fwhm);
}

// Maximum search / maximum centre of mass: one point per row (extract_max.cpp,
// extract_com.cpp).
template <typename T>
void ExtractMax(const ImageView<T>& image, const MethodParams& params, BandedPoints* out);
template <typename T>
void ExtractCom(const ImageView<T>& image, const MethodParams& params, BandedPoints* out);
// Brightest plateau of a row (first maximum); false if the row is empty.
template <typename T>
LinePeak FindRowMaximum(const T* row, int n);
// The peak max and com measure on line y of `image`: the brightest plateau at
// or above `threshold`, not touching the line's ends, whose FWHM (above
// o.background) passes the width check (WidthAccepted: a narrow one must
// continue on the adjacent lines). When the row maximum is rejected for its
// measured width (a hot pixel narrower than min_width, or a blob wider than
// max_width, brighter than the stripe), the row's other local-maximum plateaus
// are tried, brightest first, rather than losing the row. False when none
// passes or the maximum touches a line end (the stripe may continue outside).
// Only the row maximum's rejection is counted (one candidate per row).
template <typename T>
bool FindRowPeak(const ImageView<T>& image, int y, double threshold, const ExtractionOptions& o, LinePeak* peak,
                 double* fwhm, WidthRejections* rejected);

// Multi-maximum centre of mass: every peak of each row (extract_multicom.cpp).
template <typename T>
void ExtractMultiCom(const ImageView<T>& image, const MethodParams& params, BandedPoints* out);

}  // namespace lt

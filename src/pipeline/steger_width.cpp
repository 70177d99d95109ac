#include "pipeline/steger_width.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "pipeline/extraction_options.h"

namespace lt {

namespace {

// The width of the brightest peak of a search line, for Steger's expected
// width: its FWHM (`fwhm`, from the maximum search), unless a neighbouring
// stripe's light keeps the line above half the peak between them, as between
// saturated stripes a few pixels apart with glow or blur between them: there
// the half-maximum crossing lies beyond the neighbour (nine such stripes 6 px
// apart gave one 53 px "stripe", and a filter that smoothed them all into one).
// Walking out from the peak's plateau [first, last] to the half level, a valley
// is a dip of at least a quarter of the peak's height above `base` followed
// by a rise of as much (noise on a flank is far smaller; a neighbour's peak
// is not). On a side that meets one, the stripe's edge is where the line
// crosses halfway between the peak and the valley's lowest pixel; on the
// other, where it crosses half the peak. When either side meets a valley, the
// width is twice the shorter of the two edges' distances from the plateau's
// centre: the filter fits one stripe, not its neighbours.
template <typename T>
double WidthWithinValleys(const T* line, int n, int first, int last, double base, double fwhm) {
  const double peak = double(line[first]), half = base + 0.5 * (peak - base), dip = 0.25 * (peak - base);
  if (!(dip > 0)) return fwhm;
  const double centre = 0.5 * (first + last);
  double reach = std::numeric_limits<double>::infinity();
  bool valley = false;
  for (int dir : {-1, 1}) {
    const int start = dir < 0 ? first : last;
    double low = peak, level = half;
    for (int x = start + dir; x >= 0 && x < n && double(line[x]) > half; x += dir) {
      const double value = double(line[x]);
      low = std::min(low, value);
      if (low <= peak - dip && value >= low + dip) {
        level = 0.5 * (peak + low);
        valley = true;
        break;
      }
    }
    int x = start;
    while (x + dir >= 0 && x + dir < n && double(line[x + dir]) > level) x += dir;
    if (x + dir < 0 || x + dir >= n) continue;  // runs into the border
    const double a = double(line[x]), b = double(line[x + dir]);
    reach = std::min(reach, std::abs(x + dir * (a - level) / (a - b) - centre));
  }
  return valley && std::isfinite(reach) ? 2.0 * reach : fwhm;
}

// Steger's expected width measured on a frame whose rows are the search lines:
// from the FWHM of the brightest peak of each line (maximum search with the
// frame's threshold and width checks), taken across the stripe (times the
// cosine of its tilt, from the peaks 4 lines apart), the 90th percentile, so
// that the filter fits and the threshold holds (a narrower stripe reads brighter
// than its peak, a wider one dimmer) on nearly all of the stripe, but at most
// twice the median (a few wide peaks of ambient light do not set it); to 0.1 px,
// so that nearby frames share their kernels. kDefaultExpectedWidth when no line
// has a peak.
double MeasuredStripeWidth(const std::vector<StripePoint>& peaks) {
  constexpr int kSpan = 4;
  std::vector<double> widths;
  widths.reserve(peaks.size());
  size_t j = 0;  // first peak on line v + kSpan or later
  for (const StripePoint& p : peaks) {
    if (!(p.width > 0) || !std::isfinite(p.width)) continue;
    while (j < peaks.size() && peaks[j].v < p.v + kSpan) ++j;
    double slope = 0, best = 3.0 * kSpan;  // the stripe's shift over kSpan lines, at most 3 px a line
    for (size_t k = j; k < peaks.size() && peaks[k].v == p.v + kSpan; ++k) {
      if (std::abs(peaks[k].u - p.u) < best) {
        best = std::abs(peaks[k].u - p.u);
        slope = (peaks[k].u - p.u) / kSpan;
      }
    }
    widths.push_back(p.width / std::sqrt(1.0 + slope * slope));
  }
  if (widths.empty()) return ExtractionOptions::kDefaultExpectedWidth;
  auto at = [&](double q) {
    auto it = widths.begin() + ptrdiff_t(q * double(widths.size() - 1));
    std::nth_element(widths.begin(), it, widths.end());
    return *it;
  };
  const double median = at(0.5), p90 = at(0.9);
  return std::clamp(std::round(std::min(p90, 2.0 * median) * 10.0) / 10.0, 1.0, 200.0);
}

}  // namespace

template <typename T>
double MeasureStegerWidth(const ImageView<T>& work, double background, std::vector<StripePoint>* peaks) {
  for (StripePoint& p : *peaks) {
    // The peak's plateau holds its centre u = (first + last) / 2.
    const T* row = work.Row(int(p.v));
    int first = int(std::floor(p.u)), last = first;
    while (first > 0 && row[first - 1] == row[first]) --first;
    while (last + 1 < work.width && row[last + 1] == row[last]) ++last;
    p.width = WidthWithinValleys(row, work.width, first, last, background, p.width);
  }
  return MeasuredStripeWidth(*peaks);
}

template double MeasureStegerWidth(const ImageView<uint8_t>&, double, std::vector<StripePoint>*);
template double MeasureStegerWidth(const ImageView<uint16_t>&, double, std::vector<StripePoint>*);
template double MeasureStegerWidth(const ImageView<float>&, double, std::vector<StripePoint>*);

}  // namespace lt

// Multi-maximum centre of mass (thesis Algorithm 4): every run of pixels at or
// above the threshold is a peak candidate; its centre is the centroid of the
// intensities above the threshold (with the threshold crossings interpolated).
// Differences from the thesis: a run that is too wide is dropped whole (the thesis restarts a new run inside it), runs
// holding two peaks resolved at half height are split at the valley between
// them, runs that touch the line ends are dropped (the stripe may continue
// outside the image), widths are checked as FWHM, and a stripe peaking under
// twice the threshold is weighted above its half maximum (WidenToHalfMaximum).
#include <algorithm>
#include <cmath>

#include "pipeline/extract_methods.h"
#include "pipeline/local_background.h"

namespace lt {

namespace {

// Centroid of part [a, b] of a run of pixels >= t, weighted by the intensity
// above `floor` (t, or a valley the part was split at): the exact centroid of
// the area of max(0, I - floor) with I interpolated linearly between pixel
// centres. Inside the part this is the plain sum of x (I(x) - floor); where I
// crosses `floor` the area ends at the interpolated crossing instead of at a
// pixel centre. Summing whole pixels clipped at the floor samples a kinked
// weight with whole-pixel support and biases the centre by up to 0.028 px
// (sigma 1, noise-free); with the crossings the bias is under 0.002 px. At a
// run's ends the area reaches towards the neighbouring pixel below t; at a split
// point the valley pixel (at the floor) ends the part.
template <typename T>
bool ClippedCentroid(const T* row, int n, int a, int b, double floor, double t, double* centroid) {
  const int from = (a > 0 && double(row[a - 1]) < t) ? a - 1 : a;
  const int to = (b < n - 1 && double(row[b + 1]) < t) ? b + 1 : b;
  double area = 0, moment = 0;
  for (int x = from; x < to; ++x) {  // segment [x, x + 1]
    double y0 = double(row[x]) - floor, y1 = double(row[x + 1]) - floor;
    if (!(y0 > 0) && !(y1 > 0)) continue;
    double x0 = x, x1 = x + 1.0;
    if (y0 < 0) {
      x0 = x + y0 / (y0 - y1);
      y0 = 0;
    } else if (y1 < 0) {
      x1 = x + y0 / (y0 - y1);
      y1 = 0;
    }
    const double len = x1 - x0, s = y0 + y1;
    const double seg = 0.5 * len * s;  // trapezoid area and its centroid
    area += seg;
    moment += seg * (x0 + len * (y0 + 2 * y1) / (3 * s));
  }
  if (!(area > 0)) return false;
  *centroid = moment / area;
  return true;
}

// The floor of a whole run (one not split at a valley) whose peak stands less
// than twice the threshold above the background: its half maximum (`half`,
// below t), with [a, b] widened to the pixels above it, walking out while the
// line keeps falling. Above the threshold such a stripe leaves a sliver of a
// few pixels whose centroid follows the pixel grid, not the stripe (peak 1.05
// to 1.2 times the threshold, sigma 1 to 1.5 px, noise-free: up to 0.37 px);
// above its half maximum it is weighted as a stripe of twice the threshold
// (0.01 px). True when the line falls to `half` on both sides before the walk
// stops (at a rise or the line's end); otherwise (ambient light above the half
// maximum, a neighbour's flank, noise on the flank) [a, b] is left as it was
// and the threshold stays the floor. Stripes reaching twice the threshold keep
// the threshold as floor.
template <typename V>
bool WidenToHalfMaximum(const V* row, int n, double half, int* a, int* b) {
  int lo = *a, hi = *b;
  while (lo > 0 && double(row[lo - 1]) > half && row[lo - 1] <= row[lo]) --lo;
  while (hi < n - 1 && double(row[hi + 1]) > half && row[hi + 1] <= row[hi]) ++hi;
  if (!(lo > 0 && double(row[lo - 1]) <= half && hi < n - 1 && double(row[hi + 1]) <= half)) return false;
  *a = lo, *b = hi;
  return true;
}

// Emits the point of one part [a, b] of a run of pixels >= t; `floor` is the
// level subtracted from the weights (t, or a valley the part was split at).
template <typename T>
void EmitPart(const ImageView<T>& image, int a, int b, double floor, double t, bool whole_run, int y,
              const ExtractionOptions& o, std::vector<StripePoint>* points, WidthRejections* rejected) {
  const T* row = image.Row(y);
  const int n = image.width;
  int first = a;
  for (int x = a + 1; x <= b; ++x) {
    if (row[x] > row[first]) first = x;
  }
  int last = first;
  while (last + 1 <= b && row[last + 1] == row[first]) ++last;
  const double peak = double(row[first]);
  double fwhm = PeakFwhm(row, n, first, last, peak, o.background);
  if (!WidthAccepted(fwhm, o, rejected, image, y, LinePeak{first, last, peak}, o.background, t)) return;
  const double half = o.background + 0.5 * (peak - o.background);
  if (whole_run && half < floor && WidenToHalfMaximum(row, n, half, &a, &b)) floor = half;
  double c = 0;
  if (!ClippedCentroid(row, n, a, b, floor, std::min(floor, t), &c)) return;
  points->push_back({c, double(y), fwhm, peak, -1});
}

// A run [a, b] of pixels >= t peaking at `peak` that is a shoulder of a higher
// neighbour: on one side, across a gap of pixels below t no longer than the
// run plus 2 px, the line rises above `peak` again, and the gap never falls by
// `rise` (the threshold's height above the background) below `peak`. Noise on
// a stripe's flank leaves such islands: a pixel or two just above t, split
// from the stripe's run by one pixel just below t (sigma-4 to 8 stripes with
// 3% noise: 1-8% of the rows had an extra point 3-10 px beside the stripe). A
// stripe rises by the threshold above its surroundings; an island does not.
template <typename T>
bool ShoulderOfAHigherPeak(const T* row, int n, int a, int b, double peak, double t, double rise) {
  if (!(rise > 0)) return false;
  const int max_gap = b - a + 3;
  for (int dir : {-1, 1}) {
    double gap_min = peak;
    int x = dir < 0 ? a - 1 : b + 1;
    for (int gap = 0; x >= 0 && x < n && double(row[x]) < t && gap <= max_gap; x += dir, ++gap) {
      gap_min = std::min(gap_min, double(row[x]));
    }
    if (!(x >= 0 && x < n && double(row[x]) >= t) || !(gap_min > peak - rise)) continue;
    for (; x >= 0 && x < n && double(row[x]) >= t; x += dir) {
      if (double(row[x]) > peak) return true;
    }
  }
  return false;
}

// One run [a, b] of pixels >= t: split at valleys lower than half of both
// neighbouring peaks, then emit each part. Resolved means: heights above t, the
// next peak rising above half of the one before (a noise ripple on a tail just
// above t, where the valley is ~0 above t, does not, so it does not raise the
// part's floor: without that condition the noisy rows of the accuracy table,
// ExtractionAccuracy.DocumentedTableHolds, fail); or heights above the
// background, whichever peak comes first. The second reading
// splits a dimmer neighbour after a brighter stripe: two sigma-1.5 stripes 7 px
// apart, the right one at half the left one's peak, were measured as one point
// 2.0 px right of the bright stripe (the dim one lost), while the same pair
// mirrored was split, since the dim peak came first. Above the background a
// ripple near t cannot double the valley's level (t - background > 0 of it).
template <typename T>
void ProcessRun(const ImageView<T>& image, int a, int b, double t, int y, const ExtractionOptions& o,
                std::vector<StripePoint>* points, WidthRejections* rejected) {
  const T* row = image.Row(y);
  const int n = image.width;
  const double t_above_base = t - o.background;  // the threshold's height above the background
  // Valley v and peaks p, q (heights above t) resolved at half height above the background.
  // The peak rising from x must also be as wide as a stripe (min_width; a spike
  // on a bright stripe's flank is not, and is not split off: rendered and real
  // flanks carry noise spikes twice the valley beside them, which the narrow-
  // peak check would keep for the stripe's own light on the adjacent lines).
  const auto wide_peak = [&](int x) {
    int last = x;
    while (last + 1 <= b && row[last + 1] >= row[last]) ++last;
    int first = last;
    while (first - 1 >= x && row[first - 1] == row[last]) --first;
    const double fwhm = PeakFwhm(row, n, first, last, double(row[last]), o.background);
    return fwhm >= o.min_width;  // false for NaN
  };
  const auto resolved_above_base = [&](double v, double p, double q, int x) {
    return t_above_base > 0 && p > 2 * v + t_above_base && q > 2 * v + t_above_base && wide_peak(x);
  };
  double run_peak = double(row[a]);
  for (int x = a + 1; x <= b; ++x) run_peak = std::max(run_peak, double(row[x]));
  if (ShoulderOfAHigherPeak(row, n, a, b, run_peak, t, t_above_base)) return;
  // Peaks clipped at saturation (or equally bright): two that both reach the
  // run's top, within 1% of its height above t, are two stripes when the line
  // between them falls a quarter of that height below it. Their true heights
  // are unknown, so whether the valley lies below half of them cannot be
  // read; saturated stripes a few pixels apart with glow between them were
  // measured as one point between the two (a diffractive element's sheets).
  const double top = run_peak - t, near_top = 0.99 * top, clipped_dip = 0.25 * top;
  int part_start = a;
  double part_floor = t;
  double cur_max = double(row[a]) - t;
  bool in_valley = false;
  double vmin = 0;
  int vmin_pos = a;
  for (int x = a + 1; x <= b; ++x) {
    const double val = double(row[x]) - t;
    if (!in_valley) {
      if (val > cur_max) {
        cur_max = val;
      } else if (val < 0.5 * cur_max || (cur_max >= near_top && val <= cur_max - clipped_dip)) {
        in_valley = true;
        vmin = val;
        vmin_pos = x;
      }
    } else {
      if (val < vmin) {
        vmin = val;
        vmin_pos = x;
      } else if ((val > 2.0 * vmin && (val > 0.5 * cur_max || resolved_above_base(vmin, cur_max, val, x))) ||
                 (cur_max >= near_top && val >= near_top && val - vmin >= clipped_dip && wide_peak(x))) {
        // A second peak rises: split at the valley.
        const double valley_level = double(row[vmin_pos]);
        if (part_start > 0) {
          EmitPart(image, part_start, vmin_pos, std::max(part_floor, valley_level), t, false, y, o, points, rejected);
        }
        part_start = vmin_pos;
        part_floor = valley_level;
        cur_max = val;
        in_valley = false;
      }
    }
  }
  if (part_start > 0 && b < n - 1) EmitPart(image, part_start, b, part_floor, t, part_start == a, y, o, points, rejected);
}

// One line with the local background (local_background.h): every local-maximum
// plateau whose height above its local background B reaches t is a peak; its
// centre is the clipped centroid (as above) of r = line - B above t over the run
// of r >= t around it, split at the valleys to neighbouring peaks (the part's
// floor is then the valley level, as ProcessRun does). A run that reaches the
// end of r (the peak's flanks) without a valley gives no point.
template <typename T>
void ProcessLineLocal(const ImageView<T>& image, double t, int y, const ExtractionOptions& o,
                      std::vector<StripePoint>* points, WidthRejections* rejected) {
  const T* row = image.Row(y);
  const int n = image.width;
  double row_min = double(row[0]);
  for (int x = 1; x < n; ++x) row_min = std::min(row_min, double(row[x]));
  thread_local std::vector<LinePeak> candidates;
  thread_local LocalPeak p;
  LocalMaximumPlateaus(row, n, row_min + t, &candidates);
  int emitted = -1;  // plateau start of the last point (two candidates can climb to one peak)
  for (const LinePeak& cand : candidates) {
    if (!MeasureLocalPeak(row, n, cand.first, cand.last, t, o.window, &p)) continue;
    if (p.first == emitted) continue;
    if (!LocalWidthAccepted(p, t, o, rejected, image, y)) continue;
    const int len = int(p.r.size());
    const double* r = p.r.data();
    int a = p.first - p.s0, b = p.last - p.s0;
    while (a > 0 && r[a - 1] >= t) --a;
    while (b < len - 1 && r[b + 1] >= t) ++b;
    double floor = t;
    bool cut_a = false, cut_b = false;
    if (std::isfinite(p.valley_lo) && a <= int(p.valley_lo) - p.s0) {
      a = int(p.valley_lo) - p.s0;
      floor = std::max(floor, r[a]);
      cut_a = true;
    }
    if (std::isfinite(p.valley_hi) && b >= int(p.valley_hi) - p.s0) {
      b = int(p.valley_hi) - p.s0;
      floor = std::max(floor, r[b]);
      cut_b = true;
    }
    if ((a == 0 && !cut_a) || (b == len - 1 && !cut_b)) continue;
    // A dim stripe: above its half maximum.
    if (!cut_a && !cut_b && 0.5 * p.height < floor && WidenToHalfMaximum(r, len, 0.5 * p.height, &a, &b)) {
      floor = 0.5 * p.height;
    }
    double c = 0;
    if (!ClippedCentroid(r, len, a, b, floor, std::min(floor, t), &c)) continue;
    points->push_back({c + p.s0, double(y), p.fwhm, p.height, -1});
    emitted = p.first;
  }
}

}  // namespace

template <typename T>
void ExtractMultiCom(const ImageView<T>& image, const MethodParams& params, BandedPoints* out) {
  const ExtractionOptions& o = *params.options;
  const int n = image.width;
  const double t = params.threshold;
  out->Reset(image.height);
  ForEachBand(image.height, out->band_rows, [&](int band, int y0, int y1) {
    auto& points = out->bands[band];
    WidthRejections* rejected = &out->rejected[band];
    constexpr int kChunk = 64;
    for (int y = y0; y < y1; ++y) {
      const T* row = image.Row(y);
      if (o.background_mode == BackgroundMode::kLocal) {
        ProcessLineLocal(image, t, y, o, &points, rejected);
        continue;
      }
      int run_start = -1;
      for (int c0 = 0; c0 < n; c0 += kChunk) {
        const int c1 = std::min(n, c0 + kChunk);
        T m = row[c0];
#pragma omp simd reduction(max : m)
        for (int x = c0 + 1; x < c1; ++x) m = row[x] > m ? row[x] : m;
        if (!(double(m) >= t)) {  // nothing above the threshold in this chunk
          if (run_start >= 0) ProcessRun(image, run_start, c0 - 1, t, y, o, &points, rejected);
          run_start = -1;
          continue;
        }
        for (int x = c0; x < c1; ++x) {
          const bool above = double(row[x]) >= t;
          if (above && run_start < 0) {
            run_start = x;
          } else if (!above && run_start >= 0) {
            ProcessRun(image, run_start, x - 1, t, y, o, &points, rejected);
            run_start = -1;
          }
        }
      }
      if (run_start >= 0) ProcessRun(image, run_start, n - 1, t, y, o, &points, rejected);
    }
  });
}

template void ExtractMultiCom<uint8_t>(const ImageView<uint8_t>&, const MethodParams&, BandedPoints*);
template void ExtractMultiCom<uint16_t>(const ImageView<uint16_t>&, const MethodParams&, BandedPoints*);
template void ExtractMultiCom<float>(const ImageView<float>&, const MethodParams&, BandedPoints*);

}  // namespace lt

// Maximum search (thesis Algorithm 2), with a threshold, a width check and the
// centre of a saturated plateau instead of its last pixel; the row's peak
// (FindRowPeak) is the brightest one that passes the width check, so a hot
// pixel brighter than the stripe does not cost the row its point.
#include <algorithm>

#include "pipeline/extract_methods.h"
#include "pipeline/local_background.h"

namespace lt {

template <typename T>
LinePeak FindRowMaximum(const T* row, int n) {
  // Chunk maxima first (a vectorised reduction), then the first occurrence of
  // the overall maximum inside the first chunk that holds it.
  constexpr int kChunk = 64;
  T best = row[0];
  int best_chunk = 0;
  for (int c0 = 0; c0 < n; c0 += kChunk) {
    const int c1 = std::min(n, c0 + kChunk);
    T m = row[c0];
#pragma omp simd reduction(max : m)
    for (int x = c0 + 1; x < c1; ++x) m = row[x] > m ? row[x] : m;
    if (m > best) {
      best = m;
      best_chunk = c0;
    }
  }
  const int end = std::min(n, best_chunk + kChunk);
  int first = best_chunk;
  while (first < end && !(row[first] == best)) ++first;
  if (first == end) return {0, 0, -1.0};  // only for non-finite rows (rejected before)
  int last = first;
  while (last + 1 < n && row[last + 1] == best) ++last;
  return {first, last, double(best)};
}

namespace {

// Local-maximum plateaus at or above `threshold` (LocalMaximumPlateaus),
// brightest first (ties: leftmost first), except the one starting at `skip`.
template <typename T>
void LocalMaxima(const T* row, int n, double threshold, int skip, std::vector<LinePeak>* out) {
  LocalMaximumPlateaus(row, n, threshold, out);
  out->erase(std::remove_if(out->begin(), out->end(), [&](const LinePeak& p) { return p.first == skip; }), out->end());
  std::stable_sort(out->begin(), out->end(), [](const LinePeak& a, const LinePeak& b) { return a.value > b.value; });
}

}  // namespace

template <typename T>
bool FindRowPeak(const ImageView<T>& image, int y, double threshold, const ExtractionOptions& o, LinePeak* peak,
                 double* fwhm, WidthRejections* rejected) {
  const T* row = image.Row(y);
  const int n = image.width;
  *peak = FindRowMaximum(row, n);
  if (!(peak->value >= threshold)) return false;
  if (peak->first == 0 || peak->last == n - 1) return false;  // runs into the border
  *fwhm = PeakFwhm(row, n, peak->first, peak->last, peak->value, o.background);
  if (WidthAccepted(*fwhm, o, rejected, image, y, *peak, o.background, threshold)) return true;
  if (std::isnan(*fwhm)) return false;  // width not measurable: not a peak that hides another
  // Rare (a row whose brightest peak has the wrong width): try the others.
  // Only the row maximum is counted as rejected (one candidate per row, as
  // before; a Bayer mosaic's row would otherwise count each of its pixels).
  thread_local std::vector<LinePeak> others;
  LocalMaxima(row, n, threshold, peak->first, &others);
  WidthRejections uncounted;
  for (const LinePeak& p : others) {
    const double w = PeakFwhm(row, n, p.first, p.last, p.value, o.background);
    if (std::isnan(w)) continue;  // the flank of a higher peak
    if (WidthAccepted(w, o, &uncounted, image, y, p, o.background, threshold)) {
      *peak = p;
      *fwhm = w;
      return true;
    }
  }
  return false;
}

template <typename T>
void ExtractMax(const ImageView<T>& image, const MethodParams& params, BandedPoints* out) {
  const ExtractionOptions& o = *params.options;
  out->Reset(image.height);
  ForEachBand(image.height, out->band_rows, [&](int band, int y0, int y1) {
    auto& points = out->bands[band];
    WidthRejections& rejected = out->rejected[band];
    for (int y = y0; y < y1; ++y) {
      if (o.background_mode == BackgroundMode::kLocal) {
        thread_local LocalPeak local;
        if (!FindRowPeakLocal(image, y, params.threshold, o, &local, &rejected)) continue;
        points.push_back({0.5 * (local.first + local.last), double(y), local.fwhm, local.height, -1});
        continue;
      }
      LinePeak peak;
      double fwhm = 0;
      if (!FindRowPeak(image, y, params.threshold, o, &peak, &fwhm, &rejected)) continue;
      points.push_back({0.5 * (peak.first + peak.last), double(y), fwhm, peak.value, -1});
    }
  });
}

#define LT_INSTANTIATE(T)                                           \
  template LinePeak FindRowMaximum<T>(const T*, int);               \
  template bool FindRowPeak<T>(const ImageView<T>&, int, double, const ExtractionOptions&, LinePeak*, double*, \
                               WidthRejections*);                   \
  template void ExtractMax<T>(const ImageView<T>&, const MethodParams&, BandedPoints*);
LT_INSTANTIATE(uint8_t)
LT_INSTANTIATE(uint16_t)
LT_INSTANTIATE(float)
#undef LT_INSTANTIATE

}  // namespace lt

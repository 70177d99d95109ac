// Maximum search (thesis Algorithm 2), with a threshold, a width check and the
// centre of a saturated plateau instead of its last pixel.
#include <algorithm>

#include "pipeline/extract_methods.h"

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

template <typename T>
void ExtractMax(const ImageView<T>& image, const MethodParams& params, BandedPoints* out) {
  const ExtractionOptions& o = *params.options;
  const int n = image.width;
  out->Reset(image.height);
  ForEachBand(image.height, out->band_rows, [&](int band, int y0, int y1) {
    auto& points = out->bands[band];
    WidthRejections& rejected = out->rejected[band];
    for (int y = y0; y < y1; ++y) {
      const T* row = image.Row(y);
      LinePeak peak = FindRowMaximum(row, n);
      if (!(peak.value >= params.threshold)) continue;
      if (peak.first == 0 || peak.last == n - 1) continue;  // runs into the border
      double fwhm = PeakFwhm(row, n, peak.first, peak.last, peak.value, o.background);
      if (!WidthAccepted(fwhm, o, &rejected)) continue;
      points.push_back({0.5 * (peak.first + peak.last), double(y), fwhm, peak.value, -1});
    }
  });
}

#define LT_INSTANTIATE(T)                                           \
  template LinePeak FindRowMaximum<T>(const T*, int);               \
  template void ExtractMax<T>(const ImageView<T>&, const MethodParams&, BandedPoints*);
LT_INSTANTIATE(uint8_t)
LT_INSTANTIATE(uint16_t)
LT_INSTANTIATE(float)
#undef LT_INSTANTIATE

}  // namespace lt

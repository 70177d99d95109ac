// Maximum centre of mass (thesis Algorithm 3, corrected): the intensity-
// weighted centroid of a window around the row maximum. The thesis divides the
// sum of intensities by the window size, which is not a position; here each
// column is weighted by its intensity above the background and the sum of
// weighted columns is divided by the sum of weights.
//
// The window is centred on the centroid itself, not on the maximum pixel:
// starting from the maximum's plateau, the centroid over [c - h, c + h] is
// taken again around the new c until it moves by less than kTolerance px, each
// pixel (covering [x - 0.5, x + 0.5]) weighted by the fraction of it inside the
// window, and h = window + 0.5 (window = 1.25 FWHM unless set) plus half the
// plateau. A window placed on the maximum pixel moves by a whole pixel when two
// nearly equal pixels trade places, and the centroid of a tail cut unevenly
// jumps with it (by up to 0.4 px on noisy rendered stripes); the self-centred
// window with fractional edges moves continuously with the intensities and
// cuts a symmetric stripe symmetrically. The iteration contracts fast: the
// window's edges sit where the stripe is a few percent of its peak.
#include <algorithm>
#include <cmath>

#include "pipeline/extract_methods.h"

namespace lt {

namespace {

constexpr double kTolerance = 1e-4;
constexpr int kMaxIterations = 8;

// Centroid of max(0, line[x] - base) over [c - h, c + h], pixels weighted by the
// fraction of them inside; false when the window leaves the line or is empty.
template <typename T>
bool WindowCentroid(const T* line, int n, double c, double h, double base, double* centroid) {
  const double lo = c - h, hi = c + h;
  if (lo < -0.5 || hi > n - 0.5) return false;
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

}  // namespace

template <typename T>
void ExtractCom(const ImageView<T>& image, const MethodParams& params, BandedPoints* out) {
  const ExtractionOptions& o = *params.options;
  const int n = image.width;
  const double base = o.background;
  out->Reset(image.height);
  ForEachBand(image.height, out->band_rows, [&](int band, int y0, int y1) {
    auto& points = out->bands[band];
    for (int y = y0; y < y1; ++y) {
      const T* row = image.Row(y);
      LinePeak peak = FindRowMaximum(row, n);
      if (!(peak.value >= params.threshold)) continue;
      double fwhm = PeakFwhm(row, n, peak.first, peak.last, peak.value, base);
      if (!WidthAccepted(fwhm, o)) continue;  // NaN (border) is rejected too
      const double half = o.window > 0 ? double(o.window) : std::max(1.0, 1.25 * fwhm);
      const double h = half + 0.5 + 0.5 * (peak.last - peak.first);
      double c = 0.5 * (peak.first + peak.last), next = c;
      bool ok = true;
      for (int i = 0; i < kMaxIterations && ok; ++i) {
        ok = WindowCentroid(row, n, c, h, base, &next);
        const bool settled = std::abs(next - c) < kTolerance;
        c = next;
        if (settled) break;
      }
      if (!ok) continue;  // the window leaves the image, or holds no light
      points.push_back({c, double(y), fwhm, peak.value, -1});
    }
  });
}

template void ExtractCom<uint8_t>(const ImageView<uint8_t>&, const MethodParams&, BandedPoints*);
template void ExtractCom<uint16_t>(const ImageView<uint16_t>&, const MethodParams&, BandedPoints*);
template void ExtractCom<float>(const ImageView<float>&, const MethodParams&, BandedPoints*);

}  // namespace lt

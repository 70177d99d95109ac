// Maximum centre of mass (thesis Algorithm 3, corrected): the intensity-
// weighted centroid of a window around the row maximum. The thesis divides the
// sum of intensities by the window size, which is not a position; here each
// column is weighted by its intensity above the background and the sum of
// weighted columns is divided by the sum of weights.
#include <algorithm>
#include <cmath>

#include "pipeline/extract_methods.h"

namespace lt {

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
      const int half = o.window > 0 ? o.window : std::max(1, int(std::ceil(1.25 * fwhm)));
      const int a = peak.first - half, b = peak.last + half;
      if (a < 0 || b >= n) continue;  // the window leaves the image
      double sw = 0, swx = 0;
      for (int x = a; x <= b; ++x) {
        double w = std::max(0.0, double(row[x]) - base);
        sw += w;
        swx += w * x;
      }
      if (!(sw > 0)) continue;
      points.push_back({swx / sw, double(y), fwhm, peak.value, -1});
    }
  });
}

template void ExtractCom<uint8_t>(const ImageView<uint8_t>&, const MethodParams&, BandedPoints*);
template void ExtractCom<uint16_t>(const ImageView<uint16_t>&, const MethodParams&, BandedPoints*);
template void ExtractCom<float>(const ImageView<float>&, const MethodParams&, BandedPoints*);

}  // namespace lt

// Maximum centre of mass (thesis Algorithm 3, corrected): the intensity-
// weighted centroid of a window around the row maximum. The thesis divides the
// sum of intensities by the window size, which is not a position; here each
// column is weighted by its intensity above the background and the sum of
// weighted columns is divided by the sum of weights.
//
// The window is centred on the centroid itself, not on the maximum pixel:
// starting from the maximum's plateau, the centroid over [c - h, c + h] is
// taken again around the new c until it moves by less than 1e-4 px, each
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
#include "pipeline/local_background.h"
#include "pipeline/window_centroid.h"

namespace lt {

template <typename T>
void ExtractCom(const ImageView<T>& image, const MethodParams& params, BandedPoints* out) {
  const ExtractionOptions& o = *params.options;
  const int n = image.width;
  const double base = o.background;
  out->Reset(image.height);
  ForEachBand(image.height, out->band_rows, [&](int band, int y0, int y1) {
    auto& points = out->bands[band];
    WidthRejections& rejected = out->rejected[band];
    for (int y = y0; y < y1; ++y) {
      const T* row = image.Row(y);
      if (o.background_mode == BackgroundMode::kLocal) {
        // The same window and centroid on r = line - B (local_background.h).
        thread_local LocalPeak p;
        if (!FindRowPeakLocal(image, y, params.threshold, o, &p, &rejected)) continue;
        double c = 0;
        if (!SelfCentredCentroid(p.r.data(), int(p.r.size()), 0.5 * (p.first + p.last) - p.s0, p.half_window, 0.0,
                                 &c, p.valley_lo - p.s0, p.valley_hi - p.s0)) {
          continue;
        }
        points.push_back({c + p.s0, double(y), p.fwhm, p.height, -1});
        continue;
      }
      LinePeak peak;
      double fwhm = 0;
      if (!FindRowPeak(image, y, params.threshold, o, &peak, &fwhm, &rejected)) continue;
      const double h = ComHalfWindow(fwhm, peak.last - peak.first + 1, o.window);
      // The window stops at the valleys to neighbouring peaks (a second stripe
      // or a reflection resolved at half height).
      double lo = 0, hi = 0;
      ValleyBounds(row, n, peak.first, peak.last, peak.value, base, int(std::ceil(h)) + 1, &lo, &hi, params.threshold);
      // At the line's ends it shrinks the same way (symmetrically about the
      // centre), but not below one FWHM (at least 1 px) beyond the plateau:
      // nearer the border than that the row gives no point. (The window of 1.25
      // FWHM needed 2.9 sigma of room: a sigma-12 stripe 35 px from the
      // border, above the threshold only 26 px either side of its centre, gave
      // a point in 11 of 48 rows (1% noise), multicom in every row. A window
      // shrunk further cuts the steep part of the profile, which the pixel
      // fractions at its edges weigh inexactly.) "One FWHM" is that of the
      // flanks: a plateau's FWHM already spans the plateau (P pixels, P - 1 px
      // between its end pixels), so the flanks' is fwhm - (P - 1), the same for
      // a one-pixel maximum. Counting the plateau twice asked a saturated
      // stripe for a FWHM of room beyond its half-maximum crossings: an 8-bit
      // sigma-10 stripe clipped at 20x its peak at 60 degrees (plateau ~98 px,
      // FWHM ~108 px along the row, light above the threshold 65 px either
      // side) needed 157 px either side and gave a point in 2 of 96 rows of a
      // 320-px frame, max and multicom in every row.
      const int plateau = peak.last - peak.first + 1;
      const double min_h = std::max(1.0, fwhm - (plateau - 1)) + 0.5 * plateau;
      lo = std::max(lo, -0.5);
      hi = std::min(hi, n - 0.5);
      double c = 0;
      // No point when the window holds no light.
      if (!SelfCentredCentroid(row, n, 0.5 * (peak.first + peak.last), h, base, &c, lo, hi)) continue;
      if (std::min(c + 0.5, n - 0.5 - c) < min_h) continue;
      points.push_back({c, double(y), fwhm, peak.value, -1});
    }
  });
}

template void ExtractCom<uint8_t>(const ImageView<uint8_t>&, const MethodParams&, BandedPoints*);
template void ExtractCom<uint16_t>(const ImageView<uint16_t>&, const MethodParams&, BandedPoints*);
template void ExtractCom<float>(const ImageView<float>&, const MethodParams&, BandedPoints*);

}  // namespace lt

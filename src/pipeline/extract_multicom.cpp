// Multi-maximum centre of mass (thesis Algorithm 4): every run of pixels at or
// above the threshold is a peak candidate; its centre is the centroid of the
// intensities above the threshold. Differences from the thesis: a run that is
// too wide is dropped whole (the thesis restarts a new run inside it), runs
// holding two peaks resolved at half height are split at the valley between
// them, runs that touch the line ends are dropped (the stripe may continue
// outside the image), and widths are checked as FWHM.
#include <algorithm>
#include <cmath>

#include "pipeline/extract_methods.h"

namespace lt {

namespace {

// Emits the point of one part [a, b] of a run; `floor` is the level subtracted
// from the weights (the threshold, or a valley the part was split at).
template <typename T>
void EmitPart(const T* row, int n, int a, int b, double floor, int y, const ExtractionOptions& o,
              std::vector<StripePoint>* points, WidthRejections* rejected) {
  int first = a;
  for (int x = a + 1; x <= b; ++x) {
    if (row[x] > row[first]) first = x;
  }
  int last = first;
  while (last + 1 <= b && row[last + 1] == row[first]) ++last;
  const double peak = double(row[first]);
  double fwhm = PeakFwhm(row, n, first, last, peak, o.background);
  if (!WidthAccepted(fwhm, o, rejected)) return;
  double sw = 0, swx = 0;
  for (int x = a; x <= b; ++x) {
    double w = std::max(0.0, double(row[x]) - floor);
    sw += w;
    swx += w * x;
  }
  if (!(sw > 0)) return;
  points->push_back({swx / sw, double(y), fwhm, peak, -1});
}

// One run [a, b] of pixels >= t: split at valleys lower than half of both
// neighbouring peaks (heights above t), then emit each part.
template <typename T>
void ProcessRun(const T* row, int n, int a, int b, double t, int y, const ExtractionOptions& o,
                std::vector<StripePoint>* points, WidthRejections* rejected) {
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
      } else if (val < 0.5 * cur_max) {
        in_valley = true;
        vmin = val;
        vmin_pos = x;
      }
    } else {
      if (val < vmin) {
        vmin = val;
        vmin_pos = x;
      } else if (val > 2.0 * vmin && val > 0.5 * cur_max) {
        // A second peak rises: split at the valley.
        const double valley_level = double(row[vmin_pos]);
        if (part_start > 0) EmitPart(row, n, part_start, vmin_pos, std::max(part_floor, valley_level), y, o, points, rejected);
        part_start = vmin_pos;
        part_floor = valley_level;
        cur_max = val;
        in_valley = false;
      }
    }
  }
  if (part_start > 0 && b < n - 1) EmitPart(row, n, part_start, b, part_floor, y, o, points, rejected);
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
      int run_start = -1;
      for (int c0 = 0; c0 < n; c0 += kChunk) {
        const int c1 = std::min(n, c0 + kChunk);
        T m = row[c0];
#pragma omp simd reduction(max : m)
        for (int x = c0 + 1; x < c1; ++x) m = row[x] > m ? row[x] : m;
        if (!(double(m) >= t)) {  // nothing above the threshold in this chunk
          if (run_start >= 0) ProcessRun(row, n, run_start, c0 - 1, t, y, o, &points, rejected);
          run_start = -1;
          continue;
        }
        for (int x = c0; x < c1; ++x) {
          const bool above = double(row[x]) >= t;
          if (above && run_start < 0) {
            run_start = x;
          } else if (!above && run_start >= 0) {
            ProcessRun(row, n, run_start, x - 1, t, y, o, &points, rejected);
            run_start = -1;
          }
        }
      }
      if (run_start >= 0) ProcessRun(row, n, run_start, n - 1, t, y, o, &points, rejected);
    }
  });
}

template void ExtractMultiCom<uint8_t>(const ImageView<uint8_t>&, const MethodParams&, BandedPoints*);
template void ExtractMultiCom<uint16_t>(const ImageView<uint16_t>&, const MethodParams&, BandedPoints*);
template void ExtractMultiCom<float>(const ImageView<float>&, const MethodParams&, BandedPoints*);

}  // namespace lt

// The automatic stripe threshold (`--threshold auto`, ThresholdMode::kNoise;
// docs/extraction.md, "Automatic threshold"): per frame (per ROI), from the
// frame's own background level and noise, estimated robustly so that the few
// stripe pixels do not move them:
//
//   background  b = the median of the samples;
//   noise       s = 1.4826 * median |I(x+1) - I(x)| / sqrt(2): the MAD of first
//               differences along the search lines scaled to a Gaussian sigma
//               (a difference of two independent samples has sigma s sqrt 2;
//               a smooth background or a slope cancels in it);
//   trend       each line's running median over kTrendWindow (31) samples,
//               the least of it and those of the lines 15 before and after:
//               the background's level where it varies (ambient light, a
//               slope, texture, vignetting), blind to stripes narrower than
//               half the window across the line and to stripes running along
//               it (under 15 lines thick); spread = 2 x (its 75th
//               percentile - b): the top of a slope (evenly spread values:
//               from b - a to b + a the 75th percentile is b + a / 2); the
//               stripes and their glow (a DOE's five sheets on multi_line:
//               10-20% of the samples) do not reach the 75th percentile.
//
// threshold = b + max(k s, floor)             with --background a level, and
//           = b + spread + k s                there when spread > 2 s: the
//               background varies, so the threshold is k s above the
//               brightest of its trend (a slope or texture is not multiplied
//               by k, only the noise is);
//           = max(k s, floor)                 with --background local and for
//               steger (there the threshold is a height: above each peak's local
//               background line, which takes the ambient light's level and
//               slope away, or steger's contrast, blind to both).
// Never above full scale minus one step (integer samples): a frame whose
// background reaches that high keeps its saturated stripes (From::kFullScale,
// whose note says points under the background's top may be missing).
// k = kNoiseSigmas = 6: on a noise-only 640x480 frame the largest of its 307 200
// samples lies about 5 sigma above the mean (P(Z > 5) = 2.9e-7: 0.09 pixels a
// frame), P(Z > 6) = 9.9e-10: one pixel in ~3 300 such frames.
// floor: a height that noise-free frames (rendered float, quantized flat) need:
//   - quantized samples: k times the quantization noise q/sqrt(12) of one step q
//     (1.73 q: two steps above a flat quantized background). q is the
//     samples' step (SampleScale): 1 DN for 8/16-bit data, 16 for 12-bit data
//     stored MSB-aligned in 16 bits, and for a linearized (--transfer) frame
//     the step of the curve at the background's code value;
//   - kPeakFraction (1%) of the robust stripe peak's height above b (the 90th
//     percentile of the maxima of the lines that hold a peak: whose maximum
//     stands above k s, the quantization floor and 1% of the frame's highest
//     line maximum), so that a frame without noise does not take its faint
//     glow (interreflections, a defocused halo) as stripes, even when the
//     stripe crosses few of the lines.
// Quantized samples' medians are interpolated within their bins (one step
// wide), so noise under one step (sigma 0.5 steps) is still measured.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/image.h"
#include "sensor/image_sensor.h"

namespace lt {

struct NoiseThreshold {
  static constexpr double kNoiseSigmas = 6.0;
  static constexpr double kPeakFraction = 0.01;
  static constexpr double kVariedBackground = 2.0;  // spread / noise above which the spread counts
  static constexpr int kTrendWindow = 31;            // samples of the running median (the trend)

  double background = 0;  // b, the median sample (0 with local: not part of the threshold)
  double noise = 0;       // s, from the first differences
  double spread = 0;      // the background's top above b (from the trend's 75th percentile)
  double step = 0;        // the samples' quantization step (0: continuous)
  double peak = 0;        // the robust stripe peak's height above b
  double floor = 0;       // the floor's height above b
  double threshold = 0;   // the threshold the extractor uses
  bool local = false;     // a height above the background (local, or steger's contrast): no b
  // Which term set the threshold: the noise, the spread, the quantization
  // floor, the peak floor or the full-scale cap.
  enum class From { kNoise, kSpread, kQuantization, kPeak, kFullScale } from = From::kNoise;
};

// What the samples can resolve: their quantization step and full scale, in
// the lines' units.
struct SampleScale {
  double step = 0;  // 0: continuous (float samples)
  double full = std::numeric_limits<double>::infinity();  // inf: none known
  double median = 0;  // of the samples read (MeasureSampleScale)
};

// The scale of an image's samples: for 8/16-bit images the step is the GCD of
// the differences of about 2^16 samples read (1 for most frames, 16 for 12-bit
// data stored MSB-aligned in 16 bits; 1 when all are equal), full scale the
// type's maximum; for float images step 0 and no full scale.
template <typename T>
SampleScale MeasureSampleScale(const ImageView<T>& image);

// Estimates the threshold on `lines`, a mono image whose rows are the search
// lines (the extractor's working image: ROI, channel weights, transposition
// for column search already applied). `scale`: the samples' quantization step
// (the floor, the medians' bins) and full scale (the cap). `local`: the
// threshold is a height above the background (--background local, steger).
// Reads about 2^16 samples (every n-th line) for the medians and the trend,
// and every line for the peaks.
// `noise`: the noise when the lines cannot tell it (NaN: from the lines' first
// differences): a demosaiced mosaic's interpolation correlates neighbouring
// pixels, so its differences read the noise 2-3x too low (MosaicNoise).
template <typename T>
NoiseThreshold EstimateNoiseThreshold(const ImageView<T>& lines, const SampleScale& scale, bool local,
                                      double noise = std::numeric_limits<double>::quiet_NaN());

// The noise of the channel mix sum_c weights[c] * demosaiced channel c of a raw
// Bayer mosaic `raw` (filter `filter`, (phase_x, phase_y) its pixel (0,0)'s
// place on the sensor): each colour's noise s_c from the differences of its
// pixels two apart along the rows (its own samples, as a sigma; `step` the
// samples' quantization step, 0 continuous), then, as bilinear demosaicing
// (pipeline/demosaic.h) makes each channel at a pixel of colour c0 either the
// raw sample (variance s_c^2) or the mean of 2 or 4 other pixels (s_c^2 / 2,
// s_c^2 / 4), and the channels at one pixel come from different raw pixels
// (independent), the mix's largest variance over the three kinds of pixel:
// max over c0 of sum_c w_c^2 var_c(c0). Exact for independent pixel noise, and
// each colour counts with its own noise (a red-lit frame's R noise is not
// diluted by G's).
template <typename T>
double MosaicNoise(const ImageView<T>& raw, ColorFilter filter, int phase_x, int phase_y, const double weights[3],
                   double step);

// "37.2 (background 12 + 6 x noise 4.2)", "21.73 (background 20 + quantization
// floor 1.732, noise 0)", "25.2 (a height above the background: 6 x noise 4.2)":
// the threshold and where it came from, for notes.
std::string DescribeNoiseThreshold(const NoiseThreshold& t);

}  // namespace lt

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
//   spread      1.4826 * median |I - b|: the background's variation (ambient
//               light, texture, vignetting) as well as its noise.
//
// threshold = b + max(k s, floor)             with --background a level, and
//               b + max(k spread, floor)        there when spread > 2 s: the
//               background varies (ambient light), so the threshold rises above
//               its variation, not only its noise (the stripe pixels alone, a
//               few % of the samples, raise the spread by far less than 2x);
//           = max(k s, floor)                 with --background local and for
//               steger (there the threshold is a height: above each peak's local
//               background line, which takes the ambient light's level and
//               slope away, or steger's contrast, blind to both).
// k = kNoiseSigmas = 6: on a noise-only 640x480 frame the largest of its 307 200
// samples lies about 5 sigma above the mean (P(Z > 5) = 2.9e-7: 0.09 pixels a
// frame), P(Z > 6) = 9.9e-10: one pixel in ~3 300 such frames.
// floor: a height that noise-free frames (rendered float, quantized flat) need:
//   - integer samples: k times the quantization noise 1/sqrt(12) of one step
//     (1.73 steps: two steps above a flat quantized background);
//   - kPeakFraction (1%) of the robust stripe peak's height above b (the 90th
//     percentile of the search lines' maxima), so that a frame without noise
//     does not take its faint glow (interreflections, a defocused halo) as stripes.
// Integer samples' medians are interpolated within their unit bins, so noise
// under one step (sigma 0.5 DN) is still measured.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/image.h"

namespace lt {

struct NoiseThreshold {
  static constexpr double kNoiseSigmas = 6.0;
  static constexpr double kPeakFraction = 0.01;
  static constexpr double kVariedBackground = 2.0;  // spread / noise above which the spread counts

  double background = 0;  // b, the median sample (0 with local: not part of the threshold)
  double noise = 0;       // s, from the first differences
  double spread = 0;      // of the samples about b
  double peak = 0;        // the robust stripe peak's height above b
  double floor = 0;       // the floor's height above b
  double threshold = 0;   // the threshold the extractor uses
  bool local = false;     // a height above the background (local, or steger's contrast): no b
  // Which term set the threshold: the noise, the spread, the quantization
  // floor or the peak floor.
  enum class From { kNoise, kSpread, kQuantization, kPeak } from = From::kNoise;
};

// Estimates the threshold on `lines`, a mono image whose rows are the search
// lines (the extractor's working image: ROI, channel weights, transposition
// for column search already applied). `integer_samples`: its values are whole
// numbers (8- and 16-bit input), so the quantization floor applies and medians
// are interpolated. `local`: the threshold is a height above the background
// (--background local, steger). Reads about 2^16 samples (every
// n-th line) for the medians and every line for the peaks.
// `noise`: the noise when the lines cannot tell it (NaN: from the lines' first
// differences): a demosaiced mosaic's interpolation correlates neighbouring
// pixels, so its differences read the noise 2-3x too low (MosaicNoise).
template <typename T>
NoiseThreshold EstimateNoiseThreshold(const ImageView<T>& lines, bool integer_samples, bool local,
                                      double noise = std::numeric_limits<double>::quiet_NaN());

// The noise of a raw Bayer mosaic: from the differences of same-colour pixels
// two apart along its rows (a sigma, in the raw samples' units). A channel of
// the demosaiced image is a weighted mean of raw samples, so its noise is at
// most this; a weighted sum of channels' at most sum |w| times it.
template <typename T>
double MosaicNoise(const ImageView<T>& raw, bool integer_samples);

// "37.2 (background 12 + 6 x noise 4.2)", "21.73 (background 20 + quantization
// floor 1.732, noise 0)", "25.2 (a height above the background: 6 x noise 4.2)":
// the threshold and where it came from, for notes.
std::string DescribeNoiseThreshold(const NoiseThreshold& t);

}  // namespace lt

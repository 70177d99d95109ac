// Options of laser stripe extraction (docs/extraction.md explains each method
// and parameter).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/stripe_point.h"
#include "sensor/image_sensor.h"

namespace lt {

enum class ExtractionMethod {
  kMax,       // maximum search: brightest pixel of each row (one stripe)
  kCom,       // maximum centre of mass: intensity centroid around the maximum (one stripe)
  kMultiCom,  // multi-maximum centre of mass: every peak above a threshold (N stripes)
  kSteger,    // Steger 1998: Gaussian-derivative ridge detector (N stripes, any direction)
};

// Direction of search. kRows: stripes run roughly top to bottom and each image
// row is searched across (one point per stripe and row). kCols: stripes run
// roughly left to right and each column is searched.
enum class SearchAxis { kRows, kCols };

// What max, com and multicom subtract as the background (docs/extraction.md,
// "Local background"). kLevel: one constant level, `background`. kLocal: per peak, a
// straight line through the levels just outside the peak's window on both
// sides of it on the search line (ambient light, uneven or sloped); the
// threshold then applies to the height above that line. steger ignores kLocal
// (its second derivative is blind to a linear background).
enum class BackgroundMode { kLevel, kLocal };

// How an integer image's values encode light (docs/extraction.md, "Encoded
// images"). kLinear: proportional to it (raw sensor data, machine-vision
// cameras). kSrgb: the sRGB transfer curve (webcams, phones, most JPEGs).
// kGamma: a power law, value = light^(1/gamma). A non-linear image is
// linearized per sample through a table (2^bits entries) to linear values on
// the image's own scale (0..255 or 0..65535) before extraction, so the
// threshold, background and widths are in linear units.
enum class Transfer { kLinear, kSrgb, kGamma };

// How the threshold is set (docs/extraction.md, "Automatic threshold").
// kFixed: `threshold` (kAuto: 10% of full scale). kNoise (`--threshold auto`):
// per frame (per ROI), the frame's background plus 6 times its noise, with
// floors for noise-free frames (pipeline/auto_threshold.h).
enum class ThresholdMode { kFixed, kNoise };

// Candidate peaks (above the threshold) that max, com and multicom dropped
// for their FWHM: narrower than min_width without continuing on the adjacent
// search lines, or wider than max_width.
struct WidthRejections {
  int64_t narrow = 0;  // narrower than min_width and isolated (hot pixels, noise spikes)
  int64_t wide = 0;    // wider than max_width

  WidthRejections& operator+=(const WidthRejections& o) {
    narrow += o.narrow;
    wide += o.wide;
    return *this;
  }
};

const char* MethodName(ExtractionMethod method);
// max and com: one stripe per search line, so they cannot see several laser sheets.
inline bool FindsOneStripePerLine(ExtractionMethod method) {
  return method == ExtractionMethod::kMax || method == ExtractionMethod::kCom;
}
const char* AxisName(SearchAxis axis);
// Parse "max", "com", "multicom", "steger" / "rows", "cols"; throw
// lt::InputError(where, ...) for anything else.
ExtractionMethod ParseMethod(const std::string& text, const std::string& where);
SearchAxis ParseAxis(const std::string& text, const std::string& where);
// Parse a --transfer value: "linear", "srgb" or "gamma=G" (G in [1, 4], the
// decoding exponent: 2.2 for an image encoded with gamma 1/2.2); throw
// lt::InputError(where, ...) otherwise.
void ParseTransfer(const std::string& text, const std::string& where, Transfer* transfer, double* gamma);
// Parse a --background value: a number (mode kLevel, *level set) or "local"
// (mode kLocal, *level untouched); throw lt::InputError(where, ...) otherwise.
void ParseBackground(const std::string& text, const std::string& where, double* level, BackgroundMode* mode);
// Parse a --threshold value: a finite number (mode kFixed, *threshold set) or
// "auto" (mode kNoise, *threshold untouched); throw lt::InputError(where, ...)
// otherwise.
void ParseThreshold(const std::string& text, const std::string& where, double* threshold, ThresholdMode* mode);
// Comma-separated finite numbers ("1,0,0"; --weights), and an ROI "X,Y,W,H" of
// whole pixels (--roi); throw lt::InputError(where, ...) otherwise.
std::vector<double> ParseNumberList(const std::string& text, const std::string& where);
PixelRect ParseRoi(const std::string& text, const std::string& where);

struct ExtractionOptions {
  static constexpr double kAuto = std::numeric_limits<double>::quiet_NaN();

  ExtractionMethod method = ExtractionMethod::kCom;
  SearchAxis axis = SearchAxis::kRows;
  // Search only inside this rectangle (whole-image coordinates). The ROI
  // behaves as if the image were cropped to it: border rules apply at its edges.
  std::optional<PixelRect> roi;

  // Minimum stripe peak intensity in image units (after channel weighting).
  // kAuto: 10% of the extracted image's full scale: the sample type's (25.5 for
  // 8-bit, 6553.5 for 16-bit, 0.1 for float images) times WeightedFullScale().
  // For steger it is the low hysteresis threshold,
  // expressed as the peak intensity of a stripe of the expected width.
  double threshold = kAuto;
  // kNoise: `threshold` is ignored; each frame's is estimated from its
  // background and noise (StripeExtractor::last_noise_threshold()).
  ThresholdMode threshold_mode = ThresholdMode::kFixed;
  // Steger's high hysteresis threshold, same units: each chain must reach it
  // somewhere. kAuto: the threshold (with kNoise: at least the frame's threshold).
  double high_threshold = kAuto;
  // Level subtracted from intensities before the centre of mass (com), and
  // before the half-maximum and width estimates of every method
  // (background_mode kLevel; with kLocal only steger's width uses it).
  double background = 0;
  // kLocal: max, com and multicom estimate each peak's background locally
  // (BackgroundMode; pipeline/local_background.h).
  BackgroundMode background_mode = BackgroundMode::kLevel;
  // com: half width of the centroid window in pixels; 0 = automatic
  // (ceil(1.25 x the measured FWHM of the peak in that row)).
  int window = 0;
  // Accepted stripe width range: FWHM along the search axis in pixels
  // (max, com, multicom). A peak narrower than min_width is accepted only when
  // its light continues on the adjacent search lines (pipeline/narrow_peak.h:
  // a thin stripe, not a hot pixel); 0 accepts every width.
  // max_width 0 = no upper limit.
  double min_width = 1.5;
  double max_width = 0;
  // steger: expected stripe FWHM across the stripe in pixels; sets the filter
  // scale sigma = max(1, expected_width / (2 sqrt 3)) unless sigma > 0 is given,
  // and the conversion of the thresholds. kAuto: measured on each frame (the
  // median FWHM across the stripe of the brightest peak of each search line,
  // docs/extraction.md), kDefaultExpectedWidth where a frame has no peak.
  double expected_width = kAuto;
  static constexpr double kDefaultExpectedWidth = 5.0;
  double sigma = 0;
  // steger: stripes must cross the search axis at less than this angle from
  // its normal (degrees), otherwise the crossing point is ill-defined.
  double max_angle_deg = 75;

  // Colour input: use one channel, or a weighted sum of channels (one weight per
  // channel, e.g. 1,0,0 for a red laser). Mono images need neither.
  int channel = -1;
  std::vector<double> channel_weights;
  // A raw Bayer mosaic (one channel; kMono: not a mosaic). It is demosaiced
  // bilinearly to R, G, B (pipeline/demosaic.h) and extracted on their mean
  // (threshold and background stay in the raw image's units), or on `channel` /
  // `channel_weights` of the demosaiced R, G, B.
  ColorFilter bayer = ColorFilter::kMono;

  // How the input's values encode light (8- and 16-bit images; a float image
  // is linear and refused with another transfer). gamma: kGamma's exponent.
  Transfer transfer = Transfer::kLinear;
  double gamma = 2.2;

  // Worker threads (TBB arena); 0 = all hardware threads.
  int threads = 0;

  // The threshold is the default: 10% of full scale (kFixed, kAuto).
  bool DefaultThreshold() const { return threshold_mode == ThresholdMode::kFixed && std::isnan(threshold); }

  // Throws lt::InputError naming the offending option.
  void Check() const;
  // The channel-weighted image's scale against the input's samples: its full
  // scale is the input's times the sum of the positive weights, its black level
  // the input's times the sum of the weights. Both are 1 for one channel, a
  // mono image, and a mosaic's R, G, B mean.
  double WeightedFullScale() const;
  double WeightedLevel() const;
  // The Steger filter scale used (with expected_width kAuto: the scale for
  // kDefaultExpectedWidth; StripeExtractor::resolved_options() holds the scale of
  // its last frame).
  double SigmaUsed() const;
  // Search lines this close to the start and end of the image (or ROI) give no
  // points: ceil(3 sigma) for steger (its filter would reach outside), else 0.
  // (kAuto width: as SigmaUsed.)
  int EdgeLinesWithoutPoints() const;
};

// The bits (8 to 15) a 16-bit image's brightest sample fits in: a camera of
// that depth storing its raw DN unscaled, which the default threshold (10% of
// 65535) misses; 0 when the sample needs 16 bits or fewer than 8 (a dark frame).
int UnscaledBitDepth(double brightest);

}  // namespace lt

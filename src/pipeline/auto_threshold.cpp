#include "pipeline/auto_threshold.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <type_traits>

namespace lt {

namespace {

constexpr double kMadToSigma = 1.482602218505602;  // 1 / Phi^-1(3/4)
constexpr size_t kSamples = size_t(1) << 16;       // samples read for the medians

// The median of `v` (reordered). `step` > 0: v holds quantized values, each
// the bin of width `step` around it, and the median is interpolated within the
// middle sample's bin (noise under one step still shows in the counts).
// `folded`: v holds absolute values, so the bin of 0 is [0, step / 2).
double Median(std::vector<float>& v, double step, bool folded) {
  const size_t n = v.size();
  if (n == 0) return 0;
  auto mid = v.begin() + ptrdiff_t(n / 2);
  std::nth_element(v.begin(), mid, v.end());
  const double m = *mid;
  if (!(step > 0)) return m;
  const double h = 0.5 * step;
  const bool half_bin = folded && m < h;
  const double lo = half_bin ? 0.0 : m - h, hi = half_bin ? h : m + h;
  size_t below = 0, equal = 0;
  for (float x : v) {
    below += x < lo;
    equal += x >= lo && x < hi;
  }
  return lo + (hi - lo) * (0.5 * double(n) - double(below)) / double(equal);
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

template <typename T>
SampleScale MeasureSampleScale(const ImageView<T>& image) {
  SampleScale scale;
  const int W = image.width * image.channels, H = image.height;
  if (W <= 0 || H <= 0) return scale;
  const int step = int(std::max<size_t>(1, (size_t(W) * size_t(H) + kSamples - 1) / kSamples));
  std::vector<float> values;
  values.reserve(size_t(W) * size_t((H + step - 1) / step));
  uint64_t gcd = 0;
  const T first = image.Row(0)[0];
  for (int y = 0; y < H; y += step) {
    const T* row = image.Row(y);
    for (int x = 0; x < W; ++x) {
      values.push_back(float(row[x]));
      if constexpr (std::is_integral_v<T>) gcd = std::gcd(gcd, uint64_t(row[x] > first ? row[x] - first : first - row[x]));
    }
  }
  auto mid = values.begin() + ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  scale.median = *mid;
  if constexpr (std::is_integral_v<T>) {
    scale.step = gcd == 0 ? 1.0 : double(gcd);
    scale.full = double(std::numeric_limits<T>::max());
  }
  return scale;
}

template <typename T>
double MosaicNoise(const ImageView<T>& raw, ColorFilter filter, int phase_x, int phase_y, const double weights[3],
                   double step) {
  const int W = raw.width, H = raw.height;
  if (W < 3 || H <= 0) return 0;
  const int every = int(std::max<size_t>(1, (size_t(W) * size_t(H) + kSamples - 1) / kSamples));
  std::vector<float> diffs[3];
  for (int y = 0; y < H; y += every) {
    const T* row = raw.Row(y);
    for (int x = 0; x + 2 < W; ++x) {
      diffs[FilterChannel(filter, x + phase_x, y + phase_y)].push_back(std::abs(float(row[x + 2]) - float(row[x])));
    }
  }
  double var[3];  // each colour's variance
  for (int c = 0; c < 3; ++c) {
    const double s = kMadToSigma * Median(diffs[c], step, true) / std::sqrt(2.0);
    var[c] = s * s;
  }
  // Bilinear demosaicing: at a pixel of colour c0 the other colours are means
  // of 4 (G at R or B, R at B, B at R) or 2 (R and B at G) pixels.
  static constexpr double kShare[3][3] = {
      {1.0, 0.25, 0.25},  // at R: R, G, B
      {0.5, 1.0, 0.5},    // at G
      {0.25, 0.25, 1.0},  // at B
  };
  double worst = 0;
  for (int c0 = 0; c0 < 3; ++c0) {
    double v = 0;
    for (int c = 0; c < 3; ++c) v += weights[c] * weights[c] * kShare[c0][c] * var[c];
    worst = std::max(worst, v);
  }
  return std::sqrt(worst);
}

template <typename T>
NoiseThreshold EstimateNoiseThreshold(const ImageView<T>& lines, const SampleScale& scale, bool local, double noise) {
  NoiseThreshold t;
  t.local = local;
  t.step = scale.step;
  const int W = lines.width, H = lines.height;
  if (W <= 0 || H <= 0) return t;
  // Every `step`-th line for the medians: about kSamples samples.
  const int step = int(std::max<size_t>(1, (size_t(W) * size_t(H) + kSamples - 1) / kSamples));
  std::vector<float> values, diffs, trend, window;
  values.reserve(size_t(W) * size_t((H + step - 1) / step));
  diffs.reserve(values.capacity());
  trend.reserve(values.capacity());
  const int half = std::min(NoiseThreshold::kTrendWindow / 2, std::max(0, (W - 1) / 2));
  std::vector<float> running[3];
  // The running median of line y (windows shifted inside the line at its ends).
  auto running_median = [&](int y, std::vector<float>* out) {
    const T* row = lines.Row(y);
    out->resize(size_t(W));
    for (int x = 0; x < W; ++x) {
      const int a = std::clamp(x - half, 0, W - 1 - 2 * half);
      window.assign(row + a, row + a + 2 * half + 1);
      auto mid = window.begin() + half;
      std::nth_element(window.begin(), mid, window.end());
      (*out)[size_t(x)] = *mid;
    }
  };
  const int across = NoiseThreshold::kTrendWindow / 2;  // lines apart
  for (int y = 0; y < H; y += step) {
    const T* row = lines.Row(y);
    for (int x = 0; x < W; ++x) values.push_back(float(row[x]));
    for (int x = 0; x + 1 < W; ++x) diffs.push_back(std::abs(float(row[x + 1]) - float(row[x])));
    // The trend: the least of the running medians of this line and the lines
    // `across` before and after it. A stripe running along the line for half
    // a window raises its running median, but not theirs (unless it is
    // `across` lines thick); the background's light and texture are there too.
    running_median(y, &running[0]);
    int n = 1;
    for (int d : {-across, across}) {
      if (y + d >= 0 && y + d < H) running_median(y + d, &running[n++]);
    }
    for (int x = 0; x < W; ++x) {
      float m = running[0][size_t(x)];
      for (int i = 1; i < n; ++i) m = std::min(m, running[i][size_t(x)]);
      trend.push_back(m);
    }
  }
  const double b = Median(values, scale.step, false);
  t.noise = std::isnan(noise) ? kMadToSigma * Median(diffs, scale.step, true) / std::sqrt(2.0) : noise;
  // The background's top: the trend's 75th percentile (a DOE's sheets and
  // their glow cover up to 10-20% of a frame's samples, ambient light and
  // texture more), extrapolated as for a slope, whose values spread evenly:
  // from b - a to b + a the 75th percentile is b + a / 2, the top b + 2 x that.
  auto p75 = trend.begin() + ptrdiff_t(0.75 * double(trend.size() - 1));
  std::nth_element(trend.begin(), p75, trend.end());
  t.spread = std::max(0.0, 2.0 * (double(*p75) - b));

  const double k = NoiseThreshold::kNoiseSigmas;
  const double quantization = k * scale.step / std::sqrt(12.0);
  // The robust stripe peak: the 90th percentile of the maxima of the lines
  // that hold a peak (their maximum above the noise, the quantization floor
  // and 1% of the highest line's), so that a stripe crossing few lines still
  // sets it; 0 when no line holds one.
  std::vector<float> maxima(size_t(H), 0.0f);
  float highest = -std::numeric_limits<float>::infinity();
  for (int y = 0; y < H; ++y) {
    const T* row = lines.Row(y);
    maxima[size_t(y)] = float(*std::max_element(row, row + W));
    highest = std::max(highest, maxima[size_t(y)]);
  }
  const double stands_out = std::max({k * t.noise, quantization, NoiseThreshold::kPeakFraction * (double(highest) - b)});
  maxima.erase(std::remove_if(maxima.begin(), maxima.end(), [&](float m) { return !(double(m) - b > stands_out); }),
               maxima.end());
  if (!maxima.empty()) {
    auto p90 = maxima.begin() + ptrdiff_t(0.9 * double(maxima.size() - 1));
    std::nth_element(maxima.begin(), p90, maxima.end());
    t.peak = std::max(0.0, double(*p90) - b);
  }

  const double peak_floor = NoiseThreshold::kPeakFraction * t.peak;
  t.floor = std::max(quantization, peak_floor);
  double height = k * t.noise;
  t.from = NoiseThreshold::From::kNoise;
  if (!local && t.spread > NoiseThreshold::kVariedBackground * t.noise) {
    height = t.spread + k * t.noise;
    t.from = NoiseThreshold::From::kSpread;
  }
  if (t.floor > height) {
    height = t.floor;
    t.from = quantization >= peak_floor ? NoiseThreshold::From::kQuantization : NoiseThreshold::From::kPeak;
  }
  t.background = local ? 0.0 : b;
  t.threshold = t.background + height;
  // Below full scale: a saturated stripe still passes.
  const double cap = scale.full - std::max(scale.step, 0.0) - (local ? b : 0.0);
  if (std::isfinite(scale.full) && t.threshold > cap) {
    t.threshold = cap;
    t.from = NoiseThreshold::From::kFullScale;
  }
  return t;
}

std::string DescribeNoiseThreshold(const NoiseThreshold& t) {
  const std::string k = Num(NoiseThreshold::kNoiseSigmas);
  std::string s = Num(t.threshold) + " (";
  s += t.local ? std::string("a height above the background: ") : "background " + Num(t.background) + " + ";
  switch (t.from) {
    case NoiseThreshold::From::kNoise:
      s += k + " x noise " + Num(t.noise);
      break;
    case NoiseThreshold::From::kSpread:
      s += "spread " + Num(t.spread) + " + " + k + " x noise " + Num(t.noise) +
           ": the background varies; --background local measures stripes above it";
      break;
    case NoiseThreshold::From::kQuantization:
      s += "quantization floor " + Num(t.floor) + " (step " + Num(t.step) + "), noise " + Num(t.noise);
      break;
    case NoiseThreshold::From::kPeak:
      s += "floor " + Num(t.floor) + " at " + Num(100 * NoiseThreshold::kPeakFraction) + "% of the stripe peak " +
           Num(t.peak) + ", noise " + Num(t.noise);
      break;
    case NoiseThreshold::From::kFullScale:
      s += "capped one step below full scale; spread " + Num(t.spread) + ", noise " + Num(t.noise) +
           ": the background reaches near full scale, so stripes below its top may be missing; "
           "--background local measures stripes above it";
      break;
  }
  return s + ")";
}

#define LT_INSTANTIATE(T)                                                                                \
  template SampleScale MeasureSampleScale(const ImageView<T>&);                                          \
  template NoiseThreshold EstimateNoiseThreshold(const ImageView<T>&, const SampleScale&, bool, double); \
  template double MosaicNoise(const ImageView<T>&, ColorFilter, int, int, const double[3], double);
LT_INSTANTIATE(uint8_t)
LT_INSTANTIATE(uint16_t)
LT_INSTANTIATE(float)
#undef LT_INSTANTIATE

}  // namespace lt

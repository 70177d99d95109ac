#include "pipeline/auto_threshold.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

namespace lt {

namespace {

constexpr double kMadToSigma = 1.482602218505602;  // 1 / Phi^-1(3/4)
constexpr size_t kSamples = size_t(1) << 16;       // samples read for the medians

// The median of `v` (reordered). `integer`: v holds whole numbers, each the
// unit bin around it, and the median is interpolated within the middle
// sample's bin (noise under one step still shows in the counts). `folded`: v
// holds absolute values, so 0 stands for [0, 0.5).
double Median(std::vector<float>& v, bool integer, bool folded) {
  const size_t n = v.size();
  if (n == 0) return 0;
  auto mid = v.begin() + ptrdiff_t(n / 2);
  std::nth_element(v.begin(), mid, v.end());
  const double m = *mid;
  if (!integer) return m;
  size_t below = 0, equal = 0;
  for (float x : v) {
    below += x < m;
    equal += x == m;
  }
  const bool half_bin = folded && m == 0;
  return (half_bin ? 0.0 : m - 0.5) + (half_bin ? 0.5 : 1.0) * (0.5 * double(n) - double(below)) / double(equal);
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

template <typename T>
double MosaicNoise(const ImageView<T>& raw, bool integer_samples) {
  const int W = raw.width, H = raw.height;
  if (W < 3 || H <= 0) return 0;
  const int step = int(std::max<size_t>(1, (size_t(W) * size_t(H) + kSamples - 1) / kSamples));
  std::vector<float> diffs;
  diffs.reserve(size_t(W) * size_t((H + step - 1) / step));
  for (int y = 0; y < H; y += step) {
    const T* row = raw.Row(y);
    for (int x = 0; x + 2 < W; ++x) diffs.push_back(std::abs(float(row[x + 2]) - float(row[x])));
  }
  return kMadToSigma * Median(diffs, integer_samples, true) / std::sqrt(2.0);
}

template <typename T>
NoiseThreshold EstimateNoiseThreshold(const ImageView<T>& lines, bool integer_samples, bool local, double noise) {
  NoiseThreshold t;
  t.local = local;
  const int W = lines.width, H = lines.height;
  if (W <= 0 || H <= 0) return t;
  // Every `step`-th line for the medians: about kSamples samples.
  const int step = int(std::max<size_t>(1, (size_t(W) * size_t(H) + kSamples - 1) / kSamples));
  std::vector<float> values, diffs;
  values.reserve(size_t(W) * size_t((H + step - 1) / step));
  diffs.reserve(values.capacity());
  for (int y = 0; y < H; y += step) {
    const T* row = lines.Row(y);
    for (int x = 0; x < W; ++x) values.push_back(float(row[x]));
    for (int x = 0; x + 1 < W; ++x) diffs.push_back(std::abs(float(row[x + 1]) - float(row[x])));
  }
  const double b = Median(values, integer_samples, false);
  // The spread about the middle sample (a whole number for integer samples,
  // so that the folded bins are unit bins).
  const float centre = values[values.size() / 2];
  for (float& v : values) v = std::abs(v - centre);
  t.spread = kMadToSigma * Median(values, integer_samples, true);
  t.noise = std::isnan(noise) ? kMadToSigma * Median(diffs, integer_samples, true) / std::sqrt(2.0) : noise;
  // The robust stripe peak: the 90th percentile of the lines' maxima above b.
  std::vector<float> maxima(size_t(H), 0.0f);
  for (int y = 0; y < H; ++y) {
    const T* row = lines.Row(y);
    maxima[size_t(y)] = float(*std::max_element(row, row + W));
  }
  auto p90 = maxima.begin() + ptrdiff_t(0.9 * double(H - 1));
  std::nth_element(maxima.begin(), p90, maxima.end());
  t.peak = std::max(0.0, double(*p90) - b);

  const double k = NoiseThreshold::kNoiseSigmas;
  const double quantization = integer_samples ? k / std::sqrt(12.0) : 0.0;
  const double peak_floor = NoiseThreshold::kPeakFraction * t.peak;
  t.floor = std::max(quantization, peak_floor);
  double height = k * t.noise;
  t.from = NoiseThreshold::From::kNoise;
  if (!local && t.spread > NoiseThreshold::kVariedBackground * t.noise) {
    height = k * t.spread;
    t.from = NoiseThreshold::From::kSpread;
  }
  if (t.floor > height) {
    height = t.floor;
    t.from = quantization >= peak_floor ? NoiseThreshold::From::kQuantization : NoiseThreshold::From::kPeak;
  }
  t.background = local ? 0.0 : b;
  t.threshold = t.background + height;
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
      s += k + " x spread " + Num(t.spread) + ", above the noise " + Num(t.noise) +
           ": the background varies; --background local measures stripes above it";
      break;
    case NoiseThreshold::From::kQuantization:
      s += "quantization floor " + Num(t.floor) + ", noise " + Num(t.noise);
      break;
    case NoiseThreshold::From::kPeak:
      s += "floor " + Num(t.floor) + " at " + Num(100 * NoiseThreshold::kPeakFraction) + "% of the stripe peak " +
           Num(t.peak) + ", noise " + Num(t.noise);
      break;
  }
  return s + ")";
}

template NoiseThreshold EstimateNoiseThreshold(const ImageView<uint8_t>&, bool, bool, double);
template NoiseThreshold EstimateNoiseThreshold(const ImageView<uint16_t>&, bool, bool, double);
template NoiseThreshold EstimateNoiseThreshold(const ImageView<float>&, bool, bool, double);
template double MosaicNoise(const ImageView<uint8_t>&, bool);
template double MosaicNoise(const ImageView<uint16_t>&, bool);
template double MosaicNoise(const ImageView<float>&, bool);

}  // namespace lt

#include "sensor/image_sensor.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/random.h"
#include "sensor/param_error.h"

namespace lt {

namespace {

// log(k!) without the global state of std::lgamma (thread safety).
double LogFactorial(double k) {
  static const double kTable[] = {0.0,
                                  0.0,
                                  0.69314718055994531,
                                  1.79175946922805500,
                                  3.17805383034794562,
                                  4.78749174278204599,
                                  6.57925121201010100,
                                  8.52516136106541430,
                                  10.60460290274525023,
                                  12.80182748008146961};
  if (k < 10) return kTable[int(k)];
  double x = k + 1.0;  // Stirling series for log Γ(x)
  double ix = 1.0 / x, ix2 = ix * ix;
  return (x - 0.5) * std::log(x) - x + 0.91893853320467274 +
         ix * (1.0 / 12.0 - ix2 * (1.0 / 360.0 - ix2 * (1.0 / 1260.0 - ix2 / 1680.0)));
}

}  // namespace

// Poisson variate: inversion for small means, Hörmann's PTRS (transformed
// rejection with squeeze, 1993) for means >= 10. Exact in distribution.
double PoissonSample(Rng& rng, double mean) {
  if (!(mean > 0)) return 0.0;
  if (mean < 10.0) {
    double p = std::exp(-mean), s = p, u = rng.NextDouble();
    double k = 0;
    while (u > s && k < 200) {
      k += 1;
      p *= mean / k;
      s += p;
    }
    return k;
  }
  const double slam = std::sqrt(mean), loglam = std::log(mean);
  const double b = 0.931 + 2.53 * slam;
  const double a = -0.059 + 0.02483 * b;
  const double invalpha = 1.1239 + 1.1328 / (b - 3.4);
  const double vr = 0.9277 - 3.6224 / (b - 2.0);
  for (;;) {
    double U = rng.NextDouble() - 0.5;
    double V = rng.NextDouble();
    double us = 0.5 - std::abs(U);
    double k = std::floor((2.0 * a / us + b) * U + mean + 0.43);
    if (us >= 0.07 && V <= vr) return k;
    if (k < 0 || (us < 0.013 && V > us)) continue;
    if (std::log(V) + std::log(invalpha) - std::log(a / (us * us) + b) <= -mean + k * loglam - LogFactorial(k)) {
      return k;
    }
  }
}

namespace {

// ZIGNOR's tables: layer i (0 = the base strip with the tail beyond kZigR)
// spans |x| < x[i], and x[i + 1] / x[i] of it lies wholly under the density.
constexpr int kZigLayers = 128;
constexpr double kZigR = 3.442619855899;            // start of the tail
constexpr double kZigArea = 9.91256303526217e-3;    // area of each layer
struct Ziggurat {
  double x[kZigLayers + 1];
  double ratio[kZigLayers];
  Ziggurat() {
    auto f = [](double v) { return std::exp(-0.5 * v * v); };
    x[0] = kZigArea / f(kZigR);
    x[1] = kZigR;
    x[kZigLayers] = 0;
    for (int i = 2; i < kZigLayers; ++i) x[i] = std::sqrt(-2.0 * std::log(kZigArea / x[i - 1] + f(x[i - 1])));
    for (int i = 0; i < kZigLayers; ++i) ratio[i] = x[i + 1] / x[i];
  }
};

const Ziggurat& ZigguratTables() {
  static const Ziggurat z;
  return z;
}

uint64_t Next64(Rng& rng) { return (uint64_t(rng.NextU32()) << 32) | rng.NextU32(); }

// Uniform in (0, 1), for a logarithm: the centres of 2^52 equal intervals.
double OpenUniform(Rng& rng) { return (double(Next64(rng) >> 12) + 0.5) * 0x1p-52; }

// std::round (halves away from zero), without the library call: |v| < 2^52
// holds every value that has a fraction, and there v - trunc(v) is exact.
double RoundHalfAway(double v) {
  if (!(std::abs(v) < 0x1p52)) return v;  // an integer already (or NaN, inf)
  const double t = double(int64_t(v));
  const double f = v - t;
  return f >= 0.5 ? t + 1.0 : f <= -0.5 ? t - 1.0 : t;
}

}  // namespace

double NormalSample(Rng& rng) {
  const Ziggurat& z = ZigguratTables();
  for (;;) {
    const uint64_t bits = Next64(rng);
    const double u = 2.0 * (double(bits >> 11) * 0x1p-53) - 1.0;  // [-1, 1), 53 bits
    const int i = int(bits & (kZigLayers - 1));                    // 7 of the other 11 bits
    if (std::abs(u) < z.ratio[i]) return u * z.x[i];               // inside the layer's rectangle
    if (i == 0) {
      // The tail beyond kZigR (Marsaglia 1964).
      double x, y;
      do {
        x = std::log(OpenUniform(rng)) / kZigR;
        y = std::log(OpenUniform(rng));
      } while (-2.0 * y < x * x);
      return u < 0 ? x - kZigR : kZigR - x;
    }
    // The layer's wedge: accept under the density.
    const double x = u * z.x[i];
    const double f0 = std::exp(-0.5 * (z.x[i] * z.x[i] - x * x));
    const double f1 = std::exp(-0.5 * (z.x[i + 1] * z.x[i + 1] - x * x));
    if (f1 + rng.NextDouble() * (f0 - f1) < 1.0) return x;
  }
}

void ImageSensorParams::Check() const {
  if (qe_wavelength_m.empty()) throw ParamError("quantum_efficiency", "needs at least one wavelength");
  for (size_t i = 0; i < qe_wavelength_m.size(); ++i) {
    if (!(qe_wavelength_m[i] > 0) || (i > 0 && !(qe_wavelength_m[i] > qe_wavelength_m[i - 1]))) {
      throw ParamError("quantum_efficiency/wavelength_nm", "wavelengths must be > 0 and increasing");
    }
  }
  static const char* kNames[] = {"r", "g", "b"};
  int channels = color_filter == ColorFilter::kMono ? 1 : 3;
  for (int c = 0; c < channels; ++c) {
    std::string key = color_filter == ColorFilter::kMono ? "quantum_efficiency/mono"
                                                          : std::string("quantum_efficiency/") + kNames[c];
    if (qe[size_t(c)].size() != qe_wavelength_m.size()) {
      throw ParamError(key, "must have one value per wavelength (" + std::to_string(qe_wavelength_m.size()) + ")");
    }
    for (double q : qe[size_t(c)]) {
      if (!(q >= 0 && q <= 1)) throw ParamError(key, "must be in [0, 1], got " + FormatNumber(q));
    }
  }
  for (double l : band_wavelength_m) {
    if (!(l > 0 && std::isfinite(l))) throw ParamError("band_wavelengths_nm", "must be > 0");
  }
  if (!(full_well_e > 0 && std::isfinite(full_well_e))) {
    throw ParamError("full_well_e", "must be > 0, got " + FormatNumber(full_well_e));
  }
  if (!(system_gain_dn_per_e > 0 && std::isfinite(system_gain_dn_per_e))) {
    throw ParamError("system_gain_dn_per_e", "must be > 0, got " + FormatNumber(system_gain_dn_per_e));
  }
  if (!std::isfinite(analog_gain_db)) throw ParamError("analog_gain_db", "must be finite");
  if (!(dark_noise_e >= 0)) throw ParamError("dark_noise_e", "must be >= 0");
  if (!(dark_current_e_per_s >= 0)) throw ParamError("dark_current_e_per_s", "must be >= 0");
  if (!(black_level_dn >= 0)) throw ParamError("black_level_dn", "must be >= 0");
  if (bit_depth < 1 || bit_depth > 16) {
    throw ParamError("bit_depth", "must be in [1, 16], got " + std::to_string(bit_depth));
  }
  if (!(black_level_dn <= double((1u << bit_depth) - 1u))) {
    throw ParamError("black_level_dn", "must be <= 2^bit_depth - 1");
  }
  if (!(prnu >= 0 && prnu < 1)) throw ParamError("prnu_percent", "must be in [0, 100)");
  if (!(dsnu_e >= 0)) throw ParamError("dsnu_e", "must be >= 0");
}

ImageSensor::ImageSensor(const ImageSensorParams& params) : params_(params) { params_.Check(); }

double ImageSensor::SystemGain(std::optional<double> analog_gain_db) const {
  return params_.system_gain_dn_per_e * std::pow(10.0, analog_gain_db.value_or(params_.analog_gain_db) / 20.0);
}

double ImageSensor::SaturationDn(std::optional<double> analog_gain_db) const {
  return std::min(max_dn(), params_.black_level_dn + SystemGain(analog_gain_db) * params_.full_well_e);
}

namespace {
constexpr const char* kColorFilterNames[] = {"mono", "rggb", "bggr", "grbg", "gbrg"};  // by ColorFilter
}  // namespace

const char* ColorFilterName(ColorFilter filter) { return kColorFilterNames[int(filter)]; }

std::optional<ColorFilter> ParseColorFilter(std::string_view name) {
  for (int i = 0; i < int(std::size(kColorFilterNames)); ++i) {
    if (name == kColorFilterNames[i]) return ColorFilter(i);
  }
  return std::nullopt;
}

int FilterChannel(ColorFilter filter, int x, int y) {
  // Colour of the 2x2 tile position (row-major: (0,0) (1,0) (0,1) (1,1)).
  static const int kTiles[5][4] = {{0, 0, 0, 0}, {0, 1, 1, 2}, {2, 1, 1, 0}, {1, 0, 2, 1}, {1, 2, 0, 1}};
  return kTiles[int(filter)][(y & 1) * 2 + (x & 1)];
}

int ImageSensor::Channel(int x, int y) const { return FilterChannel(params_.color_filter, x, y); }

double ImageSensor::QuantumEfficiency(int channel, double wavelength_m) const {
  const auto& w = params_.qe_wavelength_m;
  const auto& q = params_.qe[size_t(params_.color_filter == ColorFilter::kMono ? 0 : channel)];
  if (wavelength_m <= w.front()) return q.front();
  if (wavelength_m >= w.back()) return q.back();
  size_t i = size_t(std::upper_bound(w.begin(), w.end(), wavelength_m) - w.begin());
  double s = (wavelength_m - w[i - 1]) / (w[i] - w[i - 1]);
  return (1.0 - s) * q[i - 1] + s * q[i];
}

void ImageSensor::CheckInput(const SensorExposure& in) const {
  if (in.width <= 0 || in.height <= 0) throw std::invalid_argument("SensorExposure: size must be > 0");
  for (const auto& m : in.monochromatic) {
    if (m.energy_j.width != in.width || m.energy_j.height != in.height || m.energy_j.channels != 1) {
      throw std::invalid_argument("SensorExposure: monochromatic image must be width x height x 1");
    }
    if (!(m.wavelength_m > 0)) throw std::invalid_argument("SensorExposure: wavelength must be > 0");
  }
  if (!in.broadband_j.empty() &&
      (in.broadband_j.width != in.width || in.broadband_j.height != in.height || in.broadband_j.channels != 3)) {
    throw std::invalid_argument("SensorExposure: broadband image must be width x height x 3");
  }
  if (!(in.exposure_s >= 0)) throw std::invalid_argument("SensorExposure: exposure must be >= 0");
}

Image<float> ImageSensor::MeanPhotoElectrons(const SensorExposure& in) const {
  CheckInput(in);
  Image<float> out(in.width, in.height, 1, 0.0f);
  // Electrons per joule for each (channel, source).
  std::vector<std::array<double, 3>> mono_gain;
  for (const auto& m : in.monochromatic) {
    std::array<double, 3> g;
    for (int c = 0; c < 3; ++c) g[size_t(c)] = QuantumEfficiency(c, m.wavelength_m) * PhotonsFromEnergy(1.0, m.wavelength_m);
    mono_gain.push_back(g);
  }
  double band_gain[3][3];  // [channel][band]
  for (int c = 0; c < 3; ++c) {
    for (int b = 0; b < 3; ++b) {
      double l = params_.band_wavelength_m[size_t(b)];
      band_gain[c][b] = QuantumEfficiency(c, l) * PhotonsFromEnergy(1.0, l);
    }
  }
  // Rows in parallel (in the caller's task arena): each pixel is independent.
  tbb::parallel_for(0, in.height, [&](int y) {
    for (int x = 0; x < in.width; ++x) {
      int c = Channel(x, y);
      double e = 0;
      for (size_t m = 0; m < in.monochromatic.size(); ++m) {
        e += mono_gain[m][size_t(c)] * double(in.monochromatic[m].energy_j.At(x, y));
      }
      if (!in.broadband_j.empty()) {
        for (int b = 0; b < 3; ++b) e += band_gain[c][b] * double(in.broadband_j.At(x, y, b));
      }
      out.At(x, y) = float(std::max(0.0, e));
    }
  });
  return out;
}

double ImageSensor::PrnuFactor(uint64_t pixel_index) const {
  if (params_.prnu == 0) return 1.0;
  Rng rng = Rng::For(params_.fixed_pattern_seed, 0, pixel_index, 0, kFixedPatternPurpose);
  return std::max(0.0, 1.0 + params_.prnu * rng.NextGaussian());
}

double ImageSensor::DsnuOffset(uint64_t pixel_index) const {
  if (params_.dsnu_e == 0) return 0.0;
  Rng rng = Rng::For(params_.fixed_pattern_seed, 0, pixel_index, 1, kFixedPatternPurpose);
  return params_.dsnu_e * rng.NextGaussian();
}

Image<uint16_t> ImageSensor::Expose(const SensorExposure& in, uint64_t seed, uint64_t frame) const {
  Image<float> mu = MeanPhotoElectrons(in);
  Image<uint16_t> out(in.width, in.height, 1, 0);
  const double K = SystemGain(in.analog_gain_db);
  const double dark_mean = params_.dark_current_e_per_s * in.exposure_s;
  const double max_value = max_dn();
  // Each pixel draws from its own counter-based stream, so rows run in parallel
  // and the frame is the same with any number of threads.
  tbb::parallel_for(0, in.height, [&](int y) {
    for (int x = 0; x < in.width; ++x) {
      uint64_t i = uint64_t(y) * uint64_t(in.width) + uint64_t(x);
      Rng rng = Rng::For(seed, frame, i, 0, kSensorNoisePurpose);
      double photo = PoissonSample(rng, double(mu.At(x, y)) * PrnuFactor(i));
      double dark = PoissonSample(rng, dark_mean);
      double charge = std::min(photo + dark, params_.full_well_e);
      double signal = charge + DsnuOffset(i) + (params_.dark_noise_e > 0 ? params_.dark_noise_e * NormalSample(rng) : 0.0);
      double dn = RoundHalfAway(params_.black_level_dn + K * signal);
      out.At(x, y) = uint16_t(std::clamp(dn, 0.0, max_value));
    }
  });
  return out;
}

Image<float> ImageSensor::ExpectedDn(const SensorExposure& in, bool fixed_pattern) const {
  Image<float> mu = MeanPhotoElectrons(in);
  const double K = SystemGain(in.analog_gain_db);
  const double dark_mean = params_.dark_current_e_per_s * in.exposure_s;
  tbb::parallel_for(0, in.height, [&](int y) {
    for (int x = 0; x < in.width; ++x) {
      uint64_t i = uint64_t(y) * uint64_t(in.width) + uint64_t(x);
      double gain = fixed_pattern ? PrnuFactor(i) : 1.0;
      double offset = fixed_pattern ? DsnuOffset(i) : 0.0;
      double charge = std::min(double(mu.At(x, y)) * gain + dark_mean, params_.full_well_e);
      mu.At(x, y) = float(std::clamp(params_.black_level_dn + K * (charge + offset), 0.0, max_dn()));
    }
  });
  return mu;
}

}  // namespace lt

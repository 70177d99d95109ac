// Image formation per the EMVA 1288 linear camera model.
//
// For each pixel i, with colour channel c(i) (mono: 0; Bayer: its filter colour
// R=0, G=1, B=2):
//   mean photo-electrons  μ_e = (1 + prnu_i) · Σ_light η_c(λ) · Q·λ/(h·c)
//        over the monochromatic inputs (energy Q in J at wavelength λ) and the
//        three broadband bands (energy Q_b in J, represented by wavelength λ_b);
//        η_c(λ) is the quantum efficiency of channel c, linear in λ between
//        table entries and constant beyond the ends;
//   charge  n = min(Poisson(μ_e) + Poisson(μ_I·t_exp), full_well)     [e-]
//        (photon shot noise, dark-current shot noise, saturation);
//   signal  s = n + dsnu_i + N(0, σ_d²)                                  [e-]
//        (DSNU: a fixed per-pixel dark offset; σ_d: temporal dark noise,
//        drawn by NormalSample);
//   output  y = clip(round(black_level + K·s), 0, 2^bits − 1)          [DN]
//        K = system_gain · 10^(analog_gain_db/20)  (DN per electron).
// prnu_i ~ N(0, prnu²) and dsnu_i ~ N(0, dsnu²) are fixed-pattern values drawn
// once per pixel from fixed_pattern_seed (same in every frame). Temporal noise
// of pixel i in frame f uses Rng::For(seed, f, i, 0, kSensorNoisePurpose).
//
// What the renderer provides (SensorExposure): for each pixel, the radiant
// energy in joules that reached the pixel's area during the exposure —
// Q = ∫ E dA dt = E (W/m²) · pixel area (m²) · on-time within the exposure (s) —
// as one single-channel image per monochromatic source (laser, pattern
// projector) with its wavelength, and one 3-channel image for broadband light
// (LED, environment) split into the R, G, B bands. The images hold the full RGB
// (or the monochromatic energy) at every pixel; the sensor applies the Bayer
// mosaic itself. The output is the raw mosaic, one channel.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "core/image.h"
#include "core/random.h"

namespace lt {

enum class ColorFilter { kMono, kRGGB, kBGGR, kGRBG, kGBRG };

// The scene file's and rig.json's names: "mono", "rggb", "bggr", "grbg", "gbrg".
const char* ColorFilterName(ColorFilter filter);
// The filter ColorFilterName names `name`; nullopt for any other text.
std::optional<ColorFilter> ParseColorFilter(std::string_view name);

// Colour channel (0 R, 1 G, 2 B; 0 for mono) of pixel (x, y) under a filter array
// (x, y >= 0).
int FilterChannel(ColorFilter filter, int x, int y);

constexpr double kPlanck = 6.62607015e-34;       // J·s
constexpr double kSpeedOfLight = 299792458.0;    // m/s
constexpr uint64_t kSensorNoisePurpose = 0x53454e534f524e31ull;   // temporal noise streams
constexpr uint64_t kFixedPatternPurpose = 0x53454e534f524650ull;  // PRNU/DSNU streams

// Number of photons of wavelength λ carrying energy Q: Q·λ/(h·c).
inline double PhotonsFromEnergy(double energy_j, double wavelength_m) {
  return energy_j * wavelength_m / (kPlanck * kSpeedOfLight);
}

// A Poisson variate with the given mean (exact: inversion below 10, PTRS above).
double PoissonSample(Rng& rng, double mean);
// A standard normal variate, exact in distribution: Marsaglia and Tsang's
// ziggurat (2000) in Doornik's form (ZIGNOR, 2005: 128 layers, the layer from
// bits of its own), from 64 bits of `rng` in 98.8% of the calls; a few times
// cheaper than Rng::NextGaussian's Box-Muller (a log and a cosine each).
double NormalSample(Rng& rng);

struct ImageSensorParams {
  ColorFilter color_filter = ColorFilter::kMono;
  // Quantum efficiency table: wavelengths (ascending, may be a single entry) and
  // per channel (R, G, B) the QE in [0, 1]. Mono uses qe[0] only.
  std::vector<double> qe_wavelength_m = {550e-9};
  std::array<std::vector<double>, 3> qe = {{{0.6}, {0.6}, {0.6}}};
  // Wavelength that stands for each broadband band (R, G, B).
  std::array<double, 3> band_wavelength_m = {{610e-9, 540e-9, 465e-9}};
  double full_well_e = 10000.0;
  double system_gain_dn_per_e = 0.25;  // K at 0 dB
  double analog_gain_db = 0.0;
  double dark_noise_e = 5.0;           // σ_d, temporal
  double dark_current_e_per_s = 0.0;   // μ_I
  double black_level_dn = 0.0;
  int bit_depth = 12;                  // 1..16
  double prnu = 0.0;                   // relative std of the per-pixel gain
  double dsnu_e = 0.0;                 // std of the per-pixel dark offset, electrons
  uint64_t fixed_pattern_seed = 1;

  // Throws ParamError naming the key.
  void Check() const;
};

struct MonochromaticEnergy {
  double wavelength_m = 0.0;
  Image<float> energy_j;  // 1 channel, joules per pixel
};

struct SensorExposure {
  int width = 0, height = 0;
  double exposure_s = 0.0;                       // for the dark current
  std::vector<MonochromaticEnergy> monochromatic;
  Image<float> broadband_j;                      // 3 channels (R, G, B bands) or empty
  std::optional<double> analog_gain_db;          // overrides the sensor's setting
};

class ImageSensor {
 public:
  ImageSensor() : ImageSensor(ImageSensorParams{}) {}
  explicit ImageSensor(const ImageSensorParams& params);  // checks params

  const ImageSensorParams& params() const { return params_; }
  ColorFilter color_filter() const { return params_.color_filter; }
  int bit_depth() const { return params_.bit_depth; }
  double max_dn() const { return double((1u << params_.bit_depth) - 1u); }
  // K in DN/e- at the given analogue gain (default: the configured one).
  double SystemGain(std::optional<double> analog_gain_db = std::nullopt) const;
  // The mean DN of a saturated pixel at that gain: the full well's charge above
  // the black level, or the ADC's largest value, whichever is lower.
  double SaturationDn(std::optional<double> analog_gain_db = std::nullopt) const;
  // Colour channel (0 R, 1 G, 2 B; 0 for mono) of pixel (x, y).
  int Channel(int x, int y) const;
  // Quantum efficiency of a channel at a wavelength.
  double QuantumEfficiency(int channel, double wavelength_m) const;

  // Mean photo-electrons per pixel (without PRNU), 1 channel.
  Image<float> MeanPhotoElectrons(const SensorExposure& in) const;
  // One frame of raw output, with all noise, 1 channel.
  Image<uint16_t> Expose(const SensorExposure& in, uint64_t seed, uint64_t frame) const;
  // The output without temporal noise and quantisation (fixed-pattern noise
  // included unless disabled): clip(black + K·(min(μ_e + μ_I t, full_well) + dsnu_i)).
  Image<float> ExpectedDn(const SensorExposure& in, bool fixed_pattern = true) const;

  // Fixed-pattern values of a pixel: gain factor 1 + prnu_i and offset dsnu_i (e-).
  double PrnuFactor(uint64_t pixel_index) const;
  double DsnuOffset(uint64_t pixel_index) const;

 private:
  void CheckInput(const SensorExposure& in) const;
  ImageSensorParams params_;
};

}  // namespace lt

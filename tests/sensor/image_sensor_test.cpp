// EMVA 1288 image formation: closed-form means, Poisson statistics, Bayer
// sampling, clipping, and the photon-transfer method recovering K and σ_d.
#include "sensor/image_sensor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sensor/param_error.h"

namespace lt {
namespace {

SensorExposure Flat(int w, int h, double energy_j, double wavelength_m, double exposure_s) {
  SensorExposure in;
  in.width = w;
  in.height = h;
  in.exposure_s = exposure_s;
  in.monochromatic.push_back({wavelength_m, Image<float>(w, h, 1, float(energy_j))});
  return in;
}

TEST(ImageSensor, PhotonCountAtWavelength) {
  // A 1 mW beam at 650 nm carries 3.2722e15 photons per second (Q·λ/(h·c), hc = 1.98645e-25 J·m).
  EXPECT_NEAR(PhotonsFromEnergy(1e-3, 650e-9), 3.2722e15, 0.0001e15);
  EXPECT_NEAR(PhotonsFromEnergy(1.0, 500e-9) / PhotonsFromEnergy(1.0, 1000e-9), 0.5, 1e-15);
}

TEST(ImageSensor, PoissonSamplerHasPoissonMoments) {
  Rng rng(42);
  for (double mean : {0.3, 4.0, 9.99, 10.0, 57.5, 2.5e4}) {
    const int n = 100000;
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
      double k = PoissonSample(rng, mean);
      ASSERT_EQ(k, std::floor(k));
      ASSERT_GE(k, 0);
      s += k;
      s2 += k * k;
    }
    double m = s / n, var = s2 / n - m * m;
    // Standard error of the mean sqrt(λ/n); of the variance ≈ λ·sqrt(2/n) (+ the
    // 1/λ excess kurtosis term). 5 standard errors.
    EXPECT_NEAR(m, mean, 5 * std::sqrt(mean / n)) << mean;
    EXPECT_NEAR(var, mean, 5 * mean * std::sqrt((2.0 + 1.0 / mean) / n)) << mean;
  }
}

TEST(ImageSensor, NormalSamplerIsStandardNormal) {
  // 10^6 draws: mean and variance against 0 and 1, and the share below each
  // edge against the normal distribution function (the tail beyond 3.44 and the
  // ziggurat's wedges included), each within 5 standard errors.
  Rng rng(7);
  const int n = 1000000;
  const double edges[] = {-4.0, -3.5, -3.0, -2.0, -1.0, -0.3, 0.0, 0.3, 1.0, 2.0, 3.0, 3.5, 4.0};
  std::vector<int64_t> below(std::size(edges), 0);
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double g = NormalSample(rng);
    ASSERT_TRUE(std::isfinite(g));
    s += g;
    s2 += g * g;
    for (size_t k = 0; k < std::size(edges); ++k) below[k] += g < edges[k];
  }
  const double mean = s / n, var = s2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(double(n)));
  EXPECT_NEAR(var, 1.0, 5.0 * std::sqrt(2.0 / n));
  for (size_t k = 0; k < std::size(edges); ++k) {
    const double p = 0.5 * std::erfc(-edges[k] / std::sqrt(2.0));
    EXPECT_NEAR(double(below[k]) / n, p, 5.0 * std::sqrt(p * (1.0 - p) / n)) << "below " << edges[k];
  }
}

TEST(ImageSensor, ExpectedDnIsTheLinearModel) {
  ImageSensorParams p;
  p.qe = {{{0.55}, {0.55}, {0.55}}};
  p.system_gain_dn_per_e = 0.3;
  p.analog_gain_db = 6.0;
  p.black_level_dn = 32;
  p.dark_current_e_per_s = 200;
  p.bit_depth = 12;
  p.full_well_e = 1e5;
  ImageSensor sensor(p);
  const double q = 2e-16, t = 0.01;
  Image<float> mean = sensor.ExpectedDn(Flat(4, 3, q, 650e-9, t));
  double electrons = 0.55 * q * 650e-9 / (kPlanck * kSpeedOfLight) + 200 * t;
  double k = 0.3 * std::pow(10.0, 6.0 / 20);
  EXPECT_NEAR(mean.At(2, 1), 32 + k * electrons, 1e-3);
  EXPECT_NEAR(sensor.SystemGain(), k, 1e-15);
}

TEST(ImageSensor, SaturatesAtFullWellAndClipsToBitDepth) {
  ImageSensorParams p;
  p.full_well_e = 5000;
  p.system_gain_dn_per_e = 0.02;  // full well = 100 DN
  p.black_level_dn = 10;
  p.bit_depth = 8;
  ImageSensor sensor(p);
  Image<uint16_t> img = sensor.Expose(Flat(32, 32, 1e-12, 600e-9, 1e-3), 1, 0);
  // Full well: 10 + 0.02·5000 = 110 DN, dark noise 5 e- = 0.1 DN: rounds to 110.
  for (uint16_t v : img.pixels) EXPECT_EQ(v, 110);
  EXPECT_DOUBLE_EQ(sensor.SaturationDn(), 110.0);
  EXPECT_DOUBLE_EQ(sensor.SaturationDn(6.0206), 10 + 0.02 * std::pow(10.0, 6.0206 / 20) * 5000);  // x2 gain: ~210 DN
  p.system_gain_dn_per_e = 1.0;  // full well = 5010 DN > 255
  ImageSensor clipped(p);
  EXPECT_DOUBLE_EQ(clipped.SaturationDn(), 255.0);
  for (uint16_t v : clipped.Expose(Flat(8, 8, 1e-12, 600e-9, 1e-3), 1, 0).pixels) EXPECT_EQ(v, 255);
  p.bit_depth = 16;
  ImageSensor deep(p);
  // 16 bits hold the full well: 5010 DN, with the dark noise (5 e- = 5 DN at K = 1) after saturation.
  for (uint16_t v : deep.Expose(Flat(8, 8, 1e-12, 600e-9, 1e-3), 1, 0).pixels) EXPECT_NEAR(v, 5010, 25);
}

TEST(ImageSensor, BayerPatternsSampleTheirChannel) {
  ImageSensorParams p;
  p.qe_wavelength_m = {450e-9, 650e-9};
  p.qe = {{{0.05, 0.6}, {0.4, 0.1}, {0.7, 0.02}}};
  const char* names[] = {"rggb", "bggr", "grbg", "gbrg"};
  const ColorFilter cfas[] = {ColorFilter::kRGGB, ColorFilter::kBGGR, ColorFilter::kGRBG, ColorFilter::kGBRG};
  const int expected[4][4] = {{0, 1, 1, 2}, {2, 1, 1, 0}, {1, 0, 2, 1}, {1, 2, 0, 1}};  // (0,0) (1,0) (0,1) (1,1)
  for (int c = 0; c < 4; ++c) {
    p.color_filter = cfas[c];
    ImageSensor sensor(p);
    SensorExposure in = Flat(4, 4, 1e-16, 650e-9, 1e-3);
    Image<float> e = sensor.MeanPhotoElectrons(in);
    double photons = PhotonsFromEnergy(1e-16, 650e-9);
    const double qe650[3] = {0.6, 0.1, 0.02};
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 4; ++x) {
        int ch = expected[c][(y & 1) * 2 + (x & 1)];
        EXPECT_EQ(sensor.Channel(x, y), ch) << names[c];
        EXPECT_NEAR(e.At(x, y), qe650[ch] * photons, 1e-3) << names[c] << " " << x << "," << y;
      }
    }
  }
  // Interpolated QE at 550 nm: halfway between the table entries.
  p.color_filter = ColorFilter::kRGGB;
  EXPECT_NEAR(ImageSensor(p).QuantumEfficiency(1, 550e-9), 0.25, 1e-12);
}

TEST(ImageSensor, BroadbandBandsUseTheirWavelengths) {
  ImageSensorParams p;
  p.qe = {{{0.5}, {0.5}, {0.5}}};
  ImageSensor sensor(p);
  SensorExposure in;
  in.width = in.height = 2;
  in.broadband_j = Image<float>(2, 2, 3, 0.0f);
  in.broadband_j.At(1, 1, 0) = 1e-16f;  // R band only
  in.broadband_j.At(1, 1, 2) = 2e-16f;  // and B band
  Image<float> e = sensor.MeanPhotoElectrons(in);
  double expected = 0.5 * (PhotonsFromEnergy(1e-16, 610e-9) + PhotonsFromEnergy(2e-16, 465e-9));
  EXPECT_NEAR(e.At(1, 1), expected, 1e-6 * expected);
  EXPECT_EQ(e.At(0, 0), 0.0f);
}

TEST(ImageSensor, NoiseIsDeterministicPerSeedAndFrame) {
  ImageSensor sensor;
  SensorExposure in = Flat(16, 16, 3e-16, 600e-9, 1e-3);
  EXPECT_EQ(sensor.Expose(in, 5, 3).pixels, sensor.Expose(in, 5, 3).pixels);
  EXPECT_NE(sensor.Expose(in, 5, 3).pixels, sensor.Expose(in, 5, 4).pixels);
  EXPECT_NE(sensor.Expose(in, 5, 3).pixels, sensor.Expose(in, 6, 3).pixels);
}

TEST(ImageSensor, FixedPatternNoiseHasConfiguredSpread) {
  ImageSensorParams p;
  p.prnu = 0.02;
  p.dsnu_e = 3.0;
  ImageSensor sensor(p);
  const int n = 40000;
  double g = 0, g2 = 0, o = 0, o2 = 0;
  for (int i = 0; i < n; ++i) {
    double a = sensor.PrnuFactor(uint64_t(i)), b = sensor.DsnuOffset(uint64_t(i));
    g += a, g2 += a * a, o += b, o2 += b * b;
  }
  double sg = std::sqrt(g2 / n - (g / n) * (g / n)), so = std::sqrt(o2 / n - (o / n) * (o / n));
  // Sample std of 40000 normals: relative standard error 1/sqrt(2n) = 0.35%; allow 2%.
  EXPECT_NEAR(g / n, 1.0, 0.001);
  EXPECT_NEAR(sg, 0.02, 0.02 * 0.02);
  EXPECT_NEAR(so, 3.0, 0.02 * 3.0);
  // The same pixel keeps its pattern in every frame and scene seed.
  EXPECT_EQ(sensor.PrnuFactor(17), sensor.PrnuFactor(17));
}

// EMVA 1288 photon transfer: flat fields at increasing exposure, two frames per
// point (bright and dark); temporal variance from the difference of the two
// frames (cancels PRNU/DSNU); K is the slope of σ²_y − σ²_y.dark against
// μ_y − μ_y.dark over 0–70% of saturation; σ_d = sqrt(σ²_y.dark − 1/12)/K.
TEST(ImageSensor, PhotonTransferRecoversGainAndDarkNoise) {
  ImageSensorParams p;
  p.qe = {{{0.62}, {0.62}, {0.62}}};
  p.full_well_e = 15000;
  p.system_gain_dn_per_e = 0.25;  // K
  p.dark_noise_e = 8.0;           // σ_d
  p.dark_current_e_per_s = 100;
  p.black_level_dn = 64;
  p.bit_depth = 12;
  p.prnu = 0.01;
  p.dsnu_e = 2.0;
  ImageSensor sensor(p);
  const int w = 150, h = 150;
  const double wavelength = 525e-9;
  const double irradiance_energy_per_s = 1.6e-12;  // J/s on one pixel: ~2.6e6 e-/s
  struct Stats {
    double mean, var;
  };
  uint64_t frame = 0;
  auto pair_stats = [&](double energy, double t) {
    SensorExposure in = Flat(w, h, energy, wavelength, t);
    Image<uint16_t> a = sensor.Expose(in, 99, frame++);
    Image<uint16_t> b = sensor.Expose(in, 99, frame++);
    double sa = 0, sb = 0, sd2 = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
      sa += a.pixels[i];
      sb += b.pixels[i];
      double d = double(a.pixels[i]) - double(b.pixels[i]);
      sd2 += d * d;
    }
    double n = double(a.pixels.size());
    double ma = sa / n, mb = sb / n;
    return Stats{0.5 * (ma + mb), sd2 / (2 * n) - 0.25 * (ma - mb) * (ma - mb)};
  };
  double sxy = 0, sxx = 0, dark_var_min_exposure = 0;
  const double saturation_dn = 0.25 * 15000;
  for (int k = 0; k <= 10; ++k) {
    double t = 0.1e-3 + k * 0.4e-3;  // up to 4.1 ms: ~10700 e-, 71% of full well
    Stats bright = pair_stats(irradiance_energy_per_s * t, t);
    Stats dark = pair_stats(0.0, t);
    if (k == 0) dark_var_min_exposure = dark.var;
    // The mean output is the noise-free model (averaged over the PRNU/DSNU of the
    // pixels); standard error of a 22500-pixel mean is below 0.5 DN here.
    Image<float> expected = sensor.ExpectedDn(Flat(w, h, irradiance_energy_per_s * t, wavelength, t));
    double expected_mean = 0;
    for (float v : expected.pixels) expected_mean += v;
    expected_mean /= double(expected.pixels.size());
    EXPECT_NEAR(bright.mean, expected_mean, 0.5) << t;
    double x = bright.mean - dark.mean, y = bright.var - dark.var;
    ASSERT_LT(x, 0.72 * saturation_dn);
    sxy += x * y;
    sxx += x * x;
  }
  double k_est = sxy / sxx;
  double dark_noise_est = std::sqrt(dark_var_min_exposure - 1.0 / 12.0) / k_est;
  // 22500 pixels per variance: 0.9% standard error per point, ~0.4% on the slope.
  EXPECT_NEAR(k_est, 0.25, 0.02 * 0.25);
  EXPECT_NEAR(dark_noise_est, 8.0, 0.05 * 8.0);
  RecordProperty("K_estimated", std::to_string(k_est));
  RecordProperty("dark_noise_estimated", std::to_string(dark_noise_est));
  std::printf("photon transfer: K = %.5f DN/e- (configured 0.25), sigma_d = %.4f e- (configured 8)\n", k_est,
              dark_noise_est);
}

TEST(ImageSensor, InvalidParametersNameTheirKey) {
  auto key_of = [](ImageSensorParams p) {
    try {
      ImageSensor s(p);
    } catch (const ParamError& e) {
      return e.key();
    }
    return std::string();
  };
  ImageSensorParams p;
  p.full_well_e = 0;
  EXPECT_EQ(key_of(p), "full_well_e");
  p = ImageSensorParams{};
  p.bit_depth = 0;
  EXPECT_EQ(key_of(p), "bit_depth");
  p.bit_depth = 17;
  EXPECT_EQ(key_of(p), "bit_depth");
  p = ImageSensorParams{};
  p.color_filter = ColorFilter::kRGGB;  // default tables are single-entry: still valid
  EXPECT_EQ(key_of(p), "");
  p.qe[2] = {1.5};
  EXPECT_EQ(key_of(p), "quantum_efficiency/b");
}

}  // namespace
}  // namespace lt

// SampleNoise: the samples a pixel needs for the standard error of its mean, in
// electrons, to be at most the fraction of the sensor's temporal noise; and the
// count a pixel takes, decided from its neighbours' samples, never its own.
#include "render/sample_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace lt {
namespace {

struct NoiseSetup {
  FilmOptions o;
  Image<float> rtoi;
  SampleNoise noise;
  explicit NoiseSetup(int width, int height) : rtoi(width, height, 1, 1.0f) {
    o.width = width, o.height = height, o.laser_sheets = 1;
    o.rgb_weights = Eigen::Vector3f::Zero();
    o.laser_weight = 1.0f;  // the tracked value is the laser radiance, read as electrons
    noise.fraction = 0.5;
    noise.radiance_to_irradiance = &rtoi;
    noise.inverse_max_radiance_to_irradiance = 1.0;
    noise.read_variance_e2 = 64.0;  // 8 e- dark noise
  }
};

// Samples 90 and 110 alternating: mean 100, sample variance 100 n / (n - 1).
void AddAlternating(Film* film, int x, int y, int n) {
  for (int i = 0; i < n; ++i) {
    const float v = i % 2 ? 110.0f : 90.0f;
    film->AddSample(x, y, Eigen::Vector3f::Zero(), std::span<const float>(&v, 1));
  }
}

TEST(SampleNoise, RequiredSamplesMeetTheFractionOfSensorNoise) {
  NoiseSetup s(2, 1);
  s.rtoi.At(1, 0) = 0.5f;  // half the electrons per unit radiance
  Film film(s.o);
  AddAlternating(&film, 0, 0, 4);
  AddAlternating(&film, 1, 0, 4);
  // Sensor noise sqrt(64 + 100) = 12.8 e-; half of it squared is 41: the
  // variance 100 * 4/3 needs 133.3 / 41 = 3.25 samples.
  EXPECT_NEAR(s.noise.RequiredSamples(film, 0, 0), (400.0 / 3.0) / 41.0, 1e-4);
  // Half the electrons: variance 133.3 / 4 against 0.25 (64 + 50).
  EXPECT_NEAR(s.noise.RequiredSamples(film, 1, 0), (100.0 / 3.0) / 28.5, 1e-4);
  // Fewer than two samples: no variance estimate, no bound.
  Film empty(s.o);
  EXPECT_TRUE(std::isinf(s.noise.RequiredSamples(empty, 0, 0)));
}

TEST(SampleNoise, TargetCountComesFromTheNeighboursNotThePixel) {
  NoiseSetup s(3, 3);
  s.noise.fraction = 0.1;
  Film film(s.o);
  auto all = [](int, int) { return true; };
  // The centre pixel is noisy; its neighbours are quiet (zero variance).
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      if (x == 1 && y == 1) {
        AddAlternating(&film, x, y, 4);
      } else {
        const float v = 100.0f;
        for (int i = 0; i < 4; ++i) film.AddSample(x, y, Eigen::Vector3f::Zero(), std::span<const float>(&v, 1));
      }
    }
  // The centre needs 133.3 / (0.01 * 164) = 81.3 samples; that does not count
  // for itself: its neighbours need none, so it stops at the first batch.
  EXPECT_EQ(s.noise.TargetCount(film, 1, 1, 4, 64, all), 4);
  // Each neighbour of the centre takes what the centre calls for, 4 doubled to
  // at least 81.3 (128), capped at spp.
  EXPECT_EQ(s.noise.TargetCount(film, 0, 0, 4, 64, all), 64);
  EXPECT_EQ(s.noise.TargetCount(film, 2, 1, 4, 256, all), 128);
  // With fraction 0.5 the centre needs 133.3 / (0.25 * 164) = 3.25: 2 doubled to 4.
  s.noise.fraction = 0.5;
  EXPECT_EQ(s.noise.TargetCount(film, 0, 0, 2, 64, all), 4);
  // Neighbours that are not sampled with the budget do not count; with none
  // left the pixel takes spp.
  auto only_self = [](int x, int y) { return x == 1 && y == 1; };
  EXPECT_EQ(s.noise.TargetCount(film, 1, 1, 4, 64, only_self), 64);
}

TEST(SampleNoise, NeighbourDecidedCountsKeepTheMeanUnbiased) {
  // Heavy-tailed pixels, as where a rare path finds a bright ridge: each
  // sample is 1000 with probability 0.02, else 1 (mean 20.98). A pixel that
  // decided from its own first 4 samples would stop at 4 whenever they missed
  // the rare value (92% of pixels, mean 1): a frame mean near 3. Decided from
  // the neighbours, every pixel's count is independent of its own samples.
  constexpr int kSize = 64, kFirst = 4, kSpp = 64;
  NoiseSetup s(kSize, kSize);
  s.noise.fraction = 0.25;
  Film film(s.o);
  std::vector<std::mt19937_64> rng;
  for (int i = 0; i < kSize * kSize; ++i) rng.emplace_back(uint64_t(i) * 7919 + 1);
  auto take = [&](int x, int y, int n) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < n; ++i) {
      const float v = u(rng[size_t(y * kSize + x)]) < 0.02 ? 1000.0f : 1.0f;
      film.AddSample(x, y, Eigen::Vector3f::Zero(), std::span<const float>(&v, 1));
    }
  };
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) take(x, y, kFirst);
  auto all = [](int, int) { return true; };
  std::vector<int> target(size_t(kSize * kSize));
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) target[size_t(y * kSize + x)] = s.noise.TargetCount(film, x, y, kFirst, kSpp, all);
  double sum = 0, var_sum = 0;
  int stopped = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const int n = target[size_t(y * kSize + x)];
      take(x, y, n - kFirst);
      sum += film.MeanValue(x, y);
      var_sum += 0.02 * 0.98 * 999.0 * 999.0 / n;  // variance of this pixel's mean
      stopped += n == kFirst;
    }
  const double mean = sum / (kSize * kSize), se = std::sqrt(var_sum) / (kSize * kSize);
  EXPECT_GT(stopped, kSize * kSize / 10);  // the stop does save samples here
  EXPECT_NEAR(mean, 20.98, 4.5 * se) << "standard error " << se;
}

}  // namespace
}  // namespace lt

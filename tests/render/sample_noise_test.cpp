// SampleNoise: a pixel stops sampling when the standard error of its mean, in
// electrons, is at most the fraction of the sensor's temporal noise.
#include "render/sample_noise.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lt {
namespace {

TEST(SampleNoise, StopsWhenStandardErrorFallsBelowTheFractionOfSensorNoise) {
  FilmOptions o;
  o.width = 2, o.height = 1, o.laser_sheets = 1;
  o.rgb_weights = Eigen::Vector3f::Zero();
  o.laser_weight = 1.0f;  // the tracked value is the laser radiance, read as electrons
  Film film(o);
  Image<float> rtoi(2, 1, 1);
  rtoi.At(0, 0) = 1.0f;
  rtoi.At(1, 0) = 0.5f;  // half the electrons per unit radiance
  SampleNoise noise;
  noise.fraction = 0.5;
  noise.radiance_to_irradiance = &rtoi;
  noise.inverse_max_radiance_to_irradiance = 1.0;
  noise.read_variance_e2 = 64.0;  // 8 e- dark noise
  // Samples 90 and 110 alternate: mean 100 e-, sample variance 100 n/(n-1).
  // Sensor noise sqrt(64 + 100) = 12.8 e-; half of it is 6.4 e-, so the pixel
  // needs 100 n/(n-1)/n <= 6.4^2 = 40.96: n >= 3.44, i.e. 4 samples.
  int n = 0;
  while (!noise.Converged(film, 0, 0) && n < 100) {
    const float v = n % 2 ? 110.0f : 90.0f;
    film.AddSample(0, 0, Eigen::Vector3f::Zero(), std::span<const float>(&v, 1));
    ++n;
  }
  EXPECT_EQ(n, 4);
  // The second pixel sees half the electrons: mean 50, standard deviation 5 per
  // sample; sensor noise sqrt(64 + 50) = 10.7 e-, half is 5.34 e-:
  // 25 n/(n-1)/n <= 28.5 from n = 2 on.
  n = 0;
  while (!noise.Converged(film, 1, 0) && n < 100) {
    const float v = n % 2 ? 110.0f : 90.0f;
    film.AddSample(1, 0, Eigen::Vector3f::Zero(), std::span<const float>(&v, 1));
    ++n;
  }
  EXPECT_EQ(n, 2);
  // Fewer than two samples never converge (no variance estimate yet).
  Film empty(o);
  EXPECT_FALSE(noise.Converged(empty, 0, 0));
}

}  // namespace
}  // namespace lt

// When a pixel has enough samples (render.adaptive_noise): the Monte Carlo
// noise of its mean, in photo-electrons, against the sensor's own temporal noise
// at that signal (EMVA 1288: dark noise, quantisation, shot noise). Rendering
// past a small fraction of the sensor's noise changes the digital numbers by
// less than the sensor itself does from frame to frame.
#pragma once

#include <algorithm>

#include "core/image.h"
#include "render/film.h"

namespace lt {

struct SampleNoise {
  double fraction = 0;  // stop when standard error <= fraction * sensor noise; 0 = never stop early
  // The film's tracked value v is in electrons at the pixel whose
  // radiance-to-irradiance factor is the largest; other pixels scale by theirs.
  const Image<float>* radiance_to_irradiance = nullptr;
  double inverse_max_radiance_to_irradiance = 0;
  double read_variance_e2 = 0;  // dark noise and quantisation, electrons²

  bool Converged(const Film& film, int x, int y) const {
    const uint32_t n = film.SampleCount(x, y);
    if (n < 2) return false;
    const double scale = double(radiance_to_irradiance->At(x, y)) * inverse_max_radiance_to_irradiance;
    const double mean_e = std::max(0.0, double(film.MeanValue(x, y))) * scale;
    const double se2 = double(film.Variance(x, y)) / double(n) * scale * scale;
    return se2 <= fraction * fraction * (read_variance_e2 + mean_e);
  }
};

}  // namespace lt

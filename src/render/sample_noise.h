// When a pixel has enough samples (render.adaptive_noise): the Monte Carlo
// noise of its mean, in photo-electrons, against the sensor's own temporal noise
// at that signal (EMVA 1288: dark noise, quantisation, shot noise). Rendering
// past a small fraction of the sensor's noise changes the digital numbers by
// less than the sensor itself does from frame to frame.
//
// A pixel's count is decided from its neighbours' first samples, never from
// its own: a pixel that stops when its own samples look quiet stops more often
// when they have missed a rare bright path, and its mean is then biased low
// (by 1.2% of the demo frame's glow). With the count independent of the
// pixel's own samples, their mean stays unbiased.
#pragma once

#include <algorithm>
#include <limits>

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

  // The number of samples at which this pixel's standard error would meet the
  // bound: var(v) / n <= fraction^2 (read variance + mean), in electrons at
  // (x, y). Infinite with fewer than two samples (no variance estimate yet).
  double RequiredSamples(const Film& film, int x, int y) const {
    const uint32_t n = film.SampleCount(x, y);
    if (n < 2) return std::numeric_limits<double>::infinity();
    const double scale = double(radiance_to_irradiance->At(x, y)) * inverse_max_radiance_to_irradiance;
    const double mean_e = std::max(0.0, double(film.MeanValue(x, y))) * scale;
    const double var_e = double(film.Variance(x, y)) * scale * scale;
    return var_e / (fraction * fraction * (read_variance_e2 + mean_e));
  }

  // Samples for pixel (x, y): first_batch doubled until it reaches the largest
  // RequiredSamples of the neighbours (the 3x3 block without the pixel itself)
  // for which `sampled(x, y)` holds, at most spp; spp when none has two samples.
  template <typename Sampled>
  int TargetCount(const Film& film, int x, int y, int first_batch, int spp, Sampled&& sampled) const {
    double need = 0;
    bool any = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= film.width() || ny >= film.height()) continue;
        if (!sampled(nx, ny) || film.SampleCount(nx, ny) < 2) continue;
        need = std::max(need, RequiredSamples(film, nx, ny));
        any = true;
      }
    if (!any) return spp;
    int count = first_batch;
    while (count < spp && double(count) < need) count *= 2;
    return std::min(count, spp);
  }
};

}  // namespace lt

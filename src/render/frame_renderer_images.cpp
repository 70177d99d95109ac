// FrameRenderer's images after sampling (render/frame_renderer.h): the radiance
// images from the film, laser speckle, the ground truth of the sheet that lights
// each pixel, and the sensor's input, in rows run in parallel.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "render/frame_renderer.h"
#include "render/speckle.h"

namespace lt {

namespace {

constexpr uint64_t kSpecklePurpose = 0x535045434b4c4531ull;

}  // namespace

void FrameRenderer::RadianceFromFilm(const Film& film, const Image<float>& splat, const FrameLights& lights,
                                     int64_t frame_index, RenderedFrame* out) const {
  const Camera& cam = scene_.sensor.camera;
  const int w = cam.width(), h = cam.height();
  out->radiance = Image<float>(w, h, 4, 0.0f);
  out->laser_radiance = Image<float>(w, h, std::max(layout_.channels, 1), 0.0f);
  // Laser speckle: one fully developed field per frame over all monochromatic channels.
  Image<float> speckle;
  if (scene_.render.speckle_contrast > 0 && !lights.emitters.empty()) {
    SpeckleOptions so;
    so.wavelength = lights.emitters.front().wavelength_m;
    so.f_number = cam.working_f_number();
    so.pixel_pitch = cam.pixel_pitch_m();
    so.contrast = scene_.render.speckle_contrast;
    speckle = GenerateSpeckle(w, h, so, HashKey(seed_, uint64_t(frame_index), kSpecklePurpose));
  }
  // One pass over the film: the means, the splat, the speckle, the laser total.
  std::vector<float> row_max(size_t(h), 0.0f);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      Eigen::Vector3f rgb = film.MeanRgb(x, y);
      for (int c = 0; c < 3; ++c) out->radiance.At(x, y, c) = rgb[c];
      float total = 0;
      for (int c = 0; c < layout_.channels; ++c) {
        float& laser = out->laser_radiance.At(x, y, c);
        laser = film.MeanLaser(x, y, c) + (splat.empty() ? 0.0f : splat.At(x, y, c));
        if (!speckle.empty()) laser *= speckle.At(x, y);
        total += laser;
      }
      out->radiance.At(x, y, 3) = total;
      row_max[size_t(y)] = std::max(row_max[size_t(y)], total);
    }
  });
  const float max_laser = h > 0 ? *std::max_element(row_max.begin(), row_max.end()) : 0.0f;
  // The sheet that lights each pixel: the largest laser-sheet share, where the
  // pixel's laser radiance is at least 1% of the frame's brightest laser pixel.
  out->gt.plane = Image<float>(w, h, 1, -1.0f);
  if (!(max_laser > 0)) return;
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      if (out->radiance.At(x, y, 3) < 0.01f * max_laser) continue;
      int best = -1;
      float best_v = 0;
      for (int c = 0; c < layout_.laser_sheets; ++c) {
        if (out->laser_radiance.At(x, y, c) > best_v) best_v = out->laser_radiance.At(x, y, c), best = c;
      }
      out->gt.plane.At(x, y) = float(best);
    }
  });
}

SensorExposure FrameRenderer::ExposureOf(const RenderedFrame& frame) const {
  const SensorRig& rig = scene_.sensor;
  const Camera& cam = rig.camera;
  const ShutterFrame& sf = frame.shutter;
  const int w = cam.width(), h = cam.height();
  SensorExposure exposure;
  exposure.width = w;
  exposure.height = h;
  exposure.exposure_s = sf.exposure_s;
  exposure.analog_gain_db = sf.analog_gain_db;
  const double joules_per_radiance = cam.pixel_area_m2() * sf.exposure_s;
  for (int g = 0; g < layout_.groups; ++g) {
    MonochromaticEnergy m;
    m.wavelength_m = layout_.group_wavelength_m[size_t(g)];
    m.energy_j = Image<float>(w, h, 1, 0.0f);
    exposure.monochromatic.push_back(std::move(m));
  }
  exposure.broadband_j = Image<float>(w, h, 3, 0.0f);
  // Per row: each laser's sheets summed into its group, the pattern projector
  // into the last group, the broadband radiance in its three bands.
  tbb::parallel_for(0, h, [&](int y) {
    int channel = 0;
    for (size_t l = 0; l < rig.lasers.size(); ++l) {
      for (int s = 0; s < rig.lasers[l].sheet_count(); ++s, ++channel) {
        for (int x = 0; x < w; ++x)
          exposure.monochromatic[l].energy_j.At(x, y) += float(double(frame.laser_radiance.At(x, y, channel)) *
                                                               radiance_to_irradiance_.At(x, y) * joules_per_radiance);
      }
    }
    if (rig.pattern) {
      auto& energy = exposure.monochromatic.back().energy_j;
      for (int x = 0; x < w; ++x)
        energy.At(x, y) = float(double(frame.laser_radiance.At(x, y, channel)) * radiance_to_irradiance_.At(x, y) *
                                joules_per_radiance);
    }
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        exposure.broadband_j.At(x, y, c) =
            float(double(frame.radiance.At(x, y, c)) * radiance_to_irradiance_.At(x, y) * joules_per_radiance);
  });
  return exposure;
}

}  // namespace lt

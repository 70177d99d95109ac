#include "scene/sensor_binning.h"

namespace lt {

ImageSensorParams BinnedImageSensor(const ImageSensorParams& pixel, int n) {
  ImageSensorParams b = pixel;
  const double n2 = double(n) * n;
  b.full_well_e *= n2;
  b.system_gain_dn_per_e /= n2;
  b.dark_noise_e *= n;
  b.dark_current_e_per_s *= n2;
  b.dsnu_e *= n;
  b.prnu /= n;
  return b;
}

void BinSensorSection(nlohmann::json& sensor, const ImageSensorParams& pixel, int n) {
  if (n <= 1) return;
  const ImageSensorParams b = BinnedImageSensor(pixel, n);
  nlohmann::json& is = sensor["image_sensor"];  // an object once a key is set
  is["full_well_e"] = b.full_well_e;
  is["system_gain_dn_per_e"] = b.system_gain_dn_per_e;
  is["dark_noise_e"] = b.dark_noise_e;
  if (b.dark_current_e_per_s > 0) is["dark_current_e_per_s"] = b.dark_current_e_per_s;
  if (b.dsnu_e > 0) is["dsnu_e"] = b.dsnu_e;
  if (b.prnu > 0) is["prnu_percent"] = b.prnu * 100;
  if (!sensor.contains("camera") || !sensor["camera"].is_object()) return;
  nlohmann::json& cam = sensor["camera"];
  auto bin_centre = [n](double c) { return (c + 0.5) / n - 0.5; };  // pixel (0,0)'s centre stays at (0,0)
  if (cam.contains("resolution") && cam["resolution"].is_array() && cam["resolution"].size() == 2 &&
      cam["resolution"][0].is_number_integer() && cam["resolution"][1].is_number_integer()) {
    cam["resolution"] = {cam["resolution"][0].get<int>() / n, cam["resolution"][1].get<int>() / n};
  }
  if (cam.contains("pixel_pitch_um") && cam["pixel_pitch_um"].is_number()) {
    cam["pixel_pitch_um"] = cam["pixel_pitch_um"].get<double>() * n;
  }
  for (const char* k : {"fx", "fy"}) {
    if (cam.contains(k) && cam[k].is_number()) cam[k] = cam[k].get<double>() / n;
  }
  for (const char* k : {"cx", "cy"}) {
    if (cam.contains(k) && cam[k].is_number()) cam[k] = bin_centre(cam[k].get<double>());
  }
  if (cam.contains("principal_point_px") && cam["principal_point_px"].is_array() &&
      cam["principal_point_px"].size() == 2 && cam["principal_point_px"][0].is_number() &&
      cam["principal_point_px"][1].is_number()) {
    cam["principal_point_px"] = {bin_centre(cam["principal_point_px"][0].get<double>()),
                                 bin_centre(cam["principal_point_px"][1].get<double>())};
  }
}

}  // namespace lt

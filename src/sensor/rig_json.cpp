// SensorRigToJson (sensor/rig.h): the rig as a JSON summary (camera intrinsics and
// distortion, lasers' poses and sheet planes, image sensor settings). The parsing of
// the scene file's `sensor` section is in rig.cpp.
#include <nlohmann/json.hpp>

#include "core/pose.h"
#include "sensor/rig.h"

namespace lt {

nlohmann::json SensorRigToJson(const SensorRig& rig) {
  const Camera& c = rig.camera;
  nlohmann::json cam = {{"resolution", {c.width(), c.height()}},
                        {"fx", c.fx()},
                        {"fy", c.fy()},
                        {"cx", c.cx()},
                        {"cy", c.cy()},
                        {"pixel_pitch_um", c.pixel_pitch_m() * 1e6},
                        {"f_number", c.f_number()}};
  if (!c.is_pinhole()) cam["focus_distance_m"] = c.focus_distance_m();
  const auto& bc = c.params().brown_conrady;
  const auto& kb = c.params().fisheye;
  switch (c.distortion_model()) {
    case DistortionModel::kNone: cam["distortion"] = {{"model", "none"}}; break;
    case DistortionModel::kBrownConrady:
      cam["distortion"] = {{"model", "brown_conrady"}, {"coefficients", {bc.k1, bc.k2, bc.p1, bc.p2, bc.k3}}};
      break;
    case DistortionModel::kFisheye:
      cam["distortion"] = {{"model", "fisheye"}, {"coefficients", {kb.k1, kb.k2, kb.k3, kb.k4}}};
      break;
  }
  nlohmann::json lasers = nlohmann::json::array();
  for (const auto& l : rig.lasers) {
    nlohmann::json planes = nlohmann::json::array();
    for (int k = 0; k < l.sheet_count(); ++k) {
      Plane pl = l.SheetPlane(k);
      planes.push_back({{"n", {pl.n.x(), pl.n.y(), pl.n.z()}}, {"d", pl.d}, {"power_mw", l.sheet_power_w(k) * 1e3}});
    }
    lasers.push_back({{"power_mw", l.power_w() * 1e3},
                      {"wavelength_nm", l.wavelength_m() * 1e9},
                      {"cam_from_projector", PoseToJson(l.cam_from_projector())},
                      {"sheet_planes_in_cam", planes}});
  }
  const auto& s = rig.image_sensor.params();
  nlohmann::json sensor = {{"bit_depth", s.bit_depth},
                           {"full_well_e", s.full_well_e},
                           {"system_gain_dn_per_e", rig.image_sensor.SystemGain()},
                           {"dark_noise_e", s.dark_noise_e},
                           {"black_level_dn", s.black_level_dn}};
  sensor["color_filter"] = ColorFilterName(s.color_filter);
  // The quantum efficiency per channel, in the scene file's form: which colour
  // channels see each laser's wavelength (scan's channel weights).
  nlohmann::json qe = {{"wavelength_nm", nlohmann::json::array()}};
  for (double w : s.qe_wavelength_m) qe["wavelength_nm"].push_back(w * 1e9);
  if (s.color_filter == ColorFilter::kMono) {
    qe["mono"] = s.qe[0];
  } else {
    qe["r"] = s.qe[0], qe["g"] = s.qe[1], qe["b"] = s.qe[2];
  }
  sensor["quantum_efficiency"] = qe;
  return {{"camera", cam}, {"lasers", lasers}, {"image_sensor", sensor}};
}

}  // namespace lt

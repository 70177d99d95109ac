// A scene for command tests of the laser's ground truth and plane numbering: a
// 200 mm plane at z = 0 seen straight down from 100 mm by a 64x48 camera (50 um
// pixels, f 4.4 mm: fx 88 px, principal point (31.5, 23.5)), lit by `lasers`;
// one frame, 1 spp, no bounce, no radiance images.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace lt::test {

inline nlohmann::json PlaneScene(const nlohmann::json& lasers) {
  const std::string square = (std::filesystem::path(LT_SOURCE_DIR) / "tests/data/gltf/square.gltf").string();
  return {{"seed", 2},
          {"objects",
           {{{"name", "floor"}, {"gltf", square}, {"scale", 20}, {"material", "white"},
             {"world_from_object", {{"translation_m", {-0.1, -0.1, 0}}}}}}},
          {"materials", {{"white", {{"base_color", {0.8, 0.8, 0.8}}}}}},
          {"sensor",
           {{"camera", {{"resolution", {64, 48}}, {"pixel_pitch_um", 50}, {"focal_length_mm", 4.4}, {"f_number", 4}}},
            {"lasers", lasers},
            {"shutter", {{"frame_period_ms", 10}, {"cycle", {{{"exposure_us", 50}, {"laser", true}}}}}}}},
          {"motion",
           {{"type", "static"}, {"world_from_cam", {{"look_at", {{"eye_m", {0, 0, 0.1}}, {"target_m", {0, 0, 0}}}}}}}},
          {"render", {{"spp", 1}, {"max_bounces", 0}, {"frames", 1}}},
          {"output", {{"write_radiance", false}}}};
}

}  // namespace lt::test

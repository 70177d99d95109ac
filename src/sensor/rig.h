// The whole scanner, as configured by the scene file's `sensor` section
// (documented in docs/scene-format.md, "## sensor"). All parsing is strict:
// every object is Finish()ed, so an unknown key is an error, and invalid values
// are lt::InputError naming the file and JSON pointer.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "core/json_reader.h"
#include "sensor/camera.h"
#include "sensor/image_sensor.h"
#include "sensor/laser.h"
#include "sensor/led.h"
#include "sensor/pattern_projector.h"
#include "sensor/shutter.h"

namespace lt {

// What one rig may hold: its emitters (lasers and the pattern projector), each
// carried by the renderer as one monochromatic light, and their sheets (a
// laser's diffractive orders, the pattern projector's one), each its own film
// channel. ParseSensorRig refuses more.
constexpr int kMaxRigEmitters = 8;
constexpr int kMaxRigSheets = 64;

struct SensorRig {
  Camera camera;
  std::vector<LaserProjector> lasers;
  std::optional<PatternProjector> pattern;
  std::optional<Led> led;
  ImageSensor image_sensor;
  ShutterSchedule shutter;
};

// Reads the `sensor` section (an object with "camera" required and
// "image_sensor", "lasers", "pattern_projector", "led", "shutter" optional).
SensorRig ParseSensorRig(const json::Object& sensor_section);

// The parts, each from its own object.
Camera ParseCamera(const json::Object& o);
ImageSensor ParseImageSensor(const json::Object& o);
LaserProjector ParseLaser(const json::Object& o);
PatternProjector ParsePatternProjector(const json::Object& o);
Led ParseLed(const json::Object& o);
ShutterSchedule ParseShutter(const json::Object& o);

// Metadata of the rig for run manifests: intrinsics, distortion, lens, laser
// poses and sheet planes (camera frame), image sensor settings.
nlohmann::json SensorRigToJson(const SensorRig& rig);

}  // namespace lt

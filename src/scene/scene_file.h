// Scene files: one JSON file that references glTF geometry and holds the sensor
// rig, its motion, render settings and outputs. docs/scene-format.md documents
// every key; docs/scene.schema.json is the JSON Schema.
//
// Parsing is strict: an unknown key, a wrong type or a value out of range is an
// lt::InputError naming the file and the JSON pointer ("scene.json:
// /sensor/camera/f_number: must be > 0, got 0"). Relative paths resolve against
// the scene file's folder; a missing glTF, texture or environment map names the
// path looked for.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"
#include "scene/motion.h"
#include "scene/printed_part.h"
#include "scene/scene_materials.h"
#include "scene/scene_settings.h"
#include "sensor/rig.h"

namespace lt {

// One entry of "objects": a glTF file placed in the world.
struct SceneObject {
  std::string name;                         // unique among the objects
  std::filesystem::path gltf;               // resolved (absolute or relative to the working folder)
  Pose world_from_object = Pose::Identity();
  double scale = 1;                         // uniform, applied to the file's coordinates first (0.001: millimetres)
  std::string material;                     // a key of "materials" replacing the glTF's, or empty
};

struct SceneFile {
  std::filesystem::path path;               // the scene file as given
  uint64_t seed = 1;
  std::vector<SceneObject> objects;         // may be empty (a dark or environment-only scene)
  std::vector<SceneMaterial> materials;     // sorted by name
  Environment environment;                  // default: black
  SensorRig sensor;
  Motion motion = DefaultMotion();
  // The printed part growing along a "gcode" motion's toolpath (scene key "print").
  std::optional<PrintSettings> print;
  RenderSettings render;
  OutputSettings output;
  // The scene as read, with every path made absolute, the defaults of seed,
  // environment, render and output written out and the motion in its complete
  // parsed form: what a run writes as its scene.json so it can be reproduced.
  nlohmann::json resolved;

  // Index into `materials` of the named material, or -1.
  int FindMaterial(const std::string& name) const;
};

// Reads and checks a scene file. Errors name the file as given.
SceneFile LoadSceneFile(const std::filesystem::path& path);
// Parses scene JSON held in memory (tests); relative paths resolve against base_dir.
SceneFile ParseSceneText(const std::string& text, const std::string& display_name,
                         const std::filesystem::path& base_dir);

}  // namespace lt

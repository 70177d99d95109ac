#include "scene/scene_file.h"

#include <set>

#include "core/error.h"

namespace lt {

using json::Range;

namespace {

SceneObject ParseObject(const json::Value& value, const std::vector<SceneMaterial>& materials) {
  json::Object o(value);
  SceneObject obj;
  json::Value name = o.Get("name");
  obj.name = name.String();
  if (obj.name.empty()) name.Fail("must not be empty");
  json::Value gltf = o.Get("gltf");
  obj.gltf = gltf.ExistingFile("glTF file");
  if (auto pose = o.Find("world_from_object")) obj.world_from_object = ReadPose(*pose);
  obj.scale = o.Number("scale", obj.scale, Range::Positive());
  if (auto mat = o.Find("material")) {
    obj.material = mat->String();
    bool known = false;
    std::string names;
    for (const auto& m : materials) {
      known |= m.material.name == obj.material;
      names += (names.empty() ? "\"" : ", \"") + m.material.name + "\"";
    }
    if (!known) {
      mat->Fail("unknown material \"" + obj.material + "\"" +
                (names.empty() ? " (the scene defines no materials)" : " (known: " + names + ")"));
    }
  }
  o.Finish();
  return obj;
}

// Adds the keys of `defaults` that `target` lacks.
void AddMissing(nlohmann::json& target, const nlohmann::json& defaults) {
  for (auto it = defaults.begin(); it != defaults.end(); ++it) {
    if (!target.contains(it.key())) target[it.key()] = it.value();
  }
}

nlohmann::json Resolve(const nlohmann::json& raw, const SceneFile& s, const std::filesystem::path& base_dir) {
  nlohmann::json r = raw;
  auto absolute = [&](const std::string& p) {
    std::filesystem::path path(p);
    if (path.is_relative()) path = base_dir / path;
    return std::filesystem::absolute(path).lexically_normal().string();
  };
  // The sensor's one file reference (parsed by ParseSensorRig).
  if (r["sensor"].contains("pattern_projector") && r["sensor"]["pattern_projector"].contains("image")) {
    auto& image = r["sensor"]["pattern_projector"]["image"];
    image = absolute(image.get<std::string>());
  }
  r["seed"] = s.seed;
  for (size_t i = 0; i < s.objects.size(); ++i) {
    r["objects"][i]["gltf"] = std::filesystem::absolute(s.objects[i].gltf).lexically_normal().string();
    r["objects"][i]["scale"] = s.objects[i].scale;
  }
  for (const auto& m : s.materials) {
    if (!m.base_color_texture_path.empty()) {
      r["materials"][m.material.name]["base_color_texture"] =
          std::filesystem::absolute(m.base_color_texture_path).lexically_normal().string();
    }
  }
  if (!r.contains("environment")) {
    r["environment"] = ToJson(s.environment);
  } else if (s.environment.kind == Environment::Kind::kMap) {
    r["environment"]["exr"] = std::filesystem::absolute(s.environment.exr).lexically_normal().string();
    AddMissing(r["environment"], ToJson(s.environment));
  }
  // The motion as parsed: every type writes its own complete form, file paths absolute.
  r["motion"] = MotionToJson(s.motion);
  if (s.print) r["print"] = PrintSettingsToJson(*s.print);
  if (!r.contains("render")) r["render"] = nlohmann::json::object();
  AddMissing(r["render"], ToJson(s.render));
  if (!r.contains("output")) r["output"] = nlohmann::json::object();
  AddMissing(r["output"], ToJson(s.output));
  return r;
}

SceneFile Parse(const json::Document& doc, const std::filesystem::path& path, const std::filesystem::path& base_dir) {
  json::Value root = doc.Root();
  json::Object o(root);
  SceneFile s;
  s.path = path;
  if (auto schema = o.Find("$schema")) schema->String();
  if (auto description = o.Find("description")) description->String();
  s.seed = uint64_t(o.Integer("seed", 1, Range::NonNegative()));
  if (auto mats = o.Find("materials")) s.materials = ParseSceneMaterials(*mats);
  json::Value objects = o.Get("objects");
  std::set<std::string> names;
  for (const json::Value& v : objects.Array()) {
    SceneObject obj = ParseObject(v, s.materials);
    if (!names.insert(obj.name).second) v.Child("name").Fail("duplicate object name \"" + obj.name + "\"");
    s.objects.push_back(std::move(obj));
  }
  if (auto env = o.Find("environment")) s.environment = ParseEnvironment(*env);
  s.sensor = ParseSensorRig(o.GetObject("sensor"));
  if (auto motion = o.Find("motion")) s.motion = ParseMotion(*motion);
  if (auto print = o.Find("print")) {
    s.print = ParsePrintSettings(*print);
    if (!std::holds_alternative<GcodeMotion>(s.motion)) {
      print->Fail("needs a \"gcode\" motion (the part is printed along its toolpath), the motion is \"" +
                  MotionTypeName(s.motion) + "\"");
    }
    if (!s.print->material.empty() && s.FindMaterial(s.print->material) < 0) {
      print->Child("material").Fail("unknown material \"" + s.print->material + "\"");
    }
  }
  if (auto render = o.Find("render")) s.render = ParseRenderSettings(*render);
  if (auto output = o.Find("output")) s.output = ParseOutputSettings(*output);
  o.Finish();
  s.resolved = Resolve(root.raw(), s, base_dir);
  return s;
}

}  // namespace

int SceneFile::FindMaterial(const std::string& name) const {
  for (size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].material.name == name) return int(i);
  }
  return -1;
}

SceneFile LoadSceneFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    // A run or scene folder given for its scene file: the JSON reader would call it empty JSON.
    const bool has_scene = std::filesystem::is_regular_file(path / "scene.json", ec);
    throw InputError(path.string(), "is a folder, not a scene file" +
                                        (has_scene ? " (it holds " + (path / "scene.json").string() + ")" : std::string()));
  }
  std::filesystem::path base = path.parent_path();
  if (base.empty()) base = ".";
  return Parse(json::Document::Load(path), path, base);
}

SceneFile ParseSceneText(const std::string& text, const std::string& display_name,
                         const std::filesystem::path& base_dir) {
  return Parse(json::Document::Parse(text, display_name, base_dir), display_name, base_dir);
}

}  // namespace lt

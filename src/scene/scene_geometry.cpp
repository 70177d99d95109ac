#include "scene/scene_geometry.h"

#include <cstdio>
#include <map>

#include "core/error.h"
#include "scene/gltf_loader.h"
#include "scene/scene_file.h"

namespace lt {

size_t SceneGeometry::UniqueTriangleCount() const {
  size_t n = 0;
  for (const auto& m : meshes) n += m.TriangleCount();
  return n;
}

std::vector<bool> SceneGeometry::UsedMaterials() const {
  std::vector<bool> used(materials.size(), false);
  std::vector<bool> mesh_seen(meshes.size(), false);
  for (const SceneInstance& inst : instances) {
    if (inst.material_override >= 0) {
      if (size_t(inst.material_override) < used.size()) used[size_t(inst.material_override)] = true;
    } else if (!mesh_seen[inst.mesh]) {
      mesh_seen[inst.mesh] = true;
      for (uint32_t id : meshes[inst.mesh].triangle_material) {
        if (id < used.size()) used[id] = true;
      }
    }
  }
  return used;
}

size_t SceneGeometry::InstancedTriangleCount() const {
  size_t n = 0;
  for (const auto& i : instances) n += meshes[i.mesh].TriangleCount();
  return n;
}

Eigen::AlignedBox3d SceneGeometry::WorldBounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& inst : instances) {
    for (const auto& p : meshes[inst.mesh].positions) box.extend(inst.world_from_mesh * p.cast<double>());
  }
  return box;
}

namespace {

// A number in a warning: three significant digits.
std::string Short(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// An object larger than this is no part for a laser-line scanner (working
// ranges of centimetres to about a metre): most likely a file written in
// millimetres (many CAD and STL converters do), read as metres.
constexpr double kImplausibleObjectSizeM = 10.0;

// Warns about each object whose world bounds exceed kImplausibleObjectSizeM
// (from each mesh's bounding box through its instances: cheap for any mesh size).
void WarnImplausibleSizes(const SceneFile& scene, SceneGeometry* g) {
  std::vector<Eigen::AlignedBox3d> mesh_bounds(g->meshes.size());
  for (size_t i = 0; i < g->meshes.size(); ++i) mesh_bounds[i] = g->meshes[i].Bounds();
  std::vector<Eigen::AlignedBox3d> object_bounds(scene.objects.size());
  for (const SceneInstance& inst : g->instances) {
    if (inst.object >= object_bounds.size() || mesh_bounds[inst.mesh].isEmpty()) continue;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner = mesh_bounds[inst.mesh].corner(Eigen::AlignedBox3d::CornerType(c));
      object_bounds[inst.object].extend(inst.world_from_mesh * corner);
    }
  }
  for (size_t oi = 0; oi < scene.objects.size(); ++oi) {
    if (object_bounds[oi].isEmpty()) continue;
    const double size = object_bounds[oi].sizes().maxCoeff();
    if (size > kImplausibleObjectSizeM) {
      g->warnings.push_back("object \"" + scene.objects[oi].name + "\" is " + Short(size) +
                            " m across; glTF is in metres: if the file is in millimetres, give the object "
                            "\"scale\": 0.001");
    }
  }
}

// Camera values that only a wrong unit gives: the smallest pixels made are about
// 0.5 um, the shortest lenses (fisheyes) about 1 mm, the shortest global-shutter
// exposures about 1 us. A pitch written in millimetres or metres under
// pixel_pitch_um (0.0048, 4.8e-6), a focal length in metres under focal_length_mm
// (0.008) or an exposure in seconds under exposure_us (0.002) falls far below
// these, renders black or one blur, and is otherwise accepted without a word.
constexpr double kSmallestPixelPitchM = 0.3e-6;
constexpr double kShortestFocalLengthM = 0.1e-3;
constexpr double kShortestExposureS = 0.1e-6;

void WarnImplausibleCamera(const SensorRig& rig, SceneGeometry* g) {
  const Camera& cam = rig.camera;
  if (cam.pixel_pitch_m() < kSmallestPixelPitchM) {
    g->warnings.push_back("sensor camera pixel pitch is " + Short(cam.pixel_pitch_m() * 1e6) +
                          " um; no sensor has pixels below 0.3 um: pixel_pitch_um is in micrometres (if it is in "
                          "millimetres or metres, convert it)");
  } else if (cam.image_distance_m() < kShortestFocalLengthM) {
    g->warnings.push_back("sensor camera focal length (fx times the pixel pitch) is " +
                          Short(cam.image_distance_m() * 1e3) +
                          " mm; no lens is shorter than 0.1 mm: focal_length_mm is in millimetres (if it is in "
                          "metres, multiply it by 1000)");
  }
  const auto& cycle = rig.shutter.params().cycle;
  for (size_t i = 0; i < cycle.size(); ++i) {
    if (cycle[i].exposure_s >= kShortestExposureS) continue;
    g->warnings.push_back("sensor shutter frame \"" + cycle[i].label + "\" exposes for " +
                          Short(cycle[i].exposure_s * 1e6) +
                          " us; no camera exposes for less than 0.1 us: exposures are in microseconds (if it is in "
                          "seconds, multiply it by 1e6)");
  }
}

// A laser, pattern projector or LED farther than this from the camera is no
// part of a scanner head (baselines of millimetres to about a metre): most likely
// a translation written in millimetres where the key says metres.
constexpr double kImplausibleEmitterDistanceM = 5.0;

void WarnImplausibleRig(const SensorRig& rig, SceneGeometry* g) {
  auto check = [&](const std::string& what, const Pose& cam_from_emitter) {
    const double d = cam_from_emitter.translation().norm();
    if (!(d > kImplausibleEmitterDistanceM)) return;
    g->warnings.push_back(what + " is " + Short(d) + " m from the camera; its translation_m is in metres: if it is in "
                          "millimetres, divide it by 1000");
  };
  for (size_t i = 0; i < rig.lasers.size(); ++i) {
    check("sensor laser " + std::to_string(i), rig.lasers[i].cam_from_projector());
  }
  if (rig.pattern) check("sensor pattern projector", rig.pattern->cam_from_projector());
  if (rig.led) check("sensor LED", rig.led->cam_from_led());
  WarnImplausibleCamera(rig, g);
}

}  // namespace

SceneGeometry LoadSceneGeometry(const SceneFile& scene) {
  SceneGeometry g;
  for (const auto& m : scene.materials) g.materials.push_back(m.material);

  // A glTF file used by several objects is loaded once, with its materials if some
  // object takes them. An object with its own "material" reads TEXCOORD_0 (as a file
  // loaded without materials gives it): when the file's materials read another set
  // and the object's material has a texture to read, such an object gets a second
  // load of the geometry alone, so what it sees does not depend on the other
  // objects. Without a texture nothing reads its texture coordinates (the triangles,
  // normals and colours of both loads are the same), and it shares the first load.
  struct Loaded {
    size_t first_mesh;
    std::vector<GltfInstance> instances;
    bool uses_default_material;
    std::string metallic_by_default;
    bool texcoords_not_set_0;
  };
  std::map<std::pair<std::filesystem::path, bool>, Loaded> loaded;  // (file, with materials)
  // Each file's key, and whether some object using it takes the file's materials: a
  // file used only by objects with a "material" of their own is loaded without them
  // (GltfLoadOptions::materials), so materials that cannot be read do not refuse it.
  std::vector<std::filesystem::path> keys;
  std::map<std::filesystem::path, bool> needs_materials;
  auto takes_file_materials = [&](const SceneObject& obj) {
    return obj.material.empty() || scene.FindMaterial(obj.material) < 0;
  };
  for (const SceneObject& obj : scene.objects) {
    std::error_code ec;
    std::filesystem::path key = std::filesystem::weakly_canonical(obj.gltf, ec);
    if (ec) key = obj.gltf;
    needs_materials[key] |= takes_file_materials(obj);
    keys.push_back(std::move(key));
  }
  // Loads `obj`'s file once per (file, materials); `override_id` is the material its
  // triangles take without materials. A second load of a file (the geometry alone)
  // repeats neither its warnings nor its degenerate-triangle count.
  auto load = [&](size_t oi, const std::filesystem::path& key, bool materials, int32_t override_id) {
    const SceneObject& obj = scene.objects[oi];
    auto it = loaded.find({key, materials});
    if (it != loaded.end()) return it;
    const bool again = loaded.count({key, !materials}) != 0;
    GltfLoadOptions options;
    options.materials = materials;
    GltfAsset asset;
    try {
      asset = LoadGltf(obj.gltf, obj.gltf.string(), options);
    } catch (const InputError& e) {
      // The file's own place first; then which object of which scene file named it: for
      // a load with the file's materials, the first object that takes them (an object
      // with its own material would not need them).
      size_t named = oi;
      for (size_t j = 0; materials && j < scene.objects.size(); ++j) {
        if (keys[j] == key && takes_file_materials(scene.objects[j])) {
          named = j;
          break;
        }
      }
      throw InputError(e.where(), e.message() + " (object \"" + scene.objects[named].name + "\", /objects/" +
                                      std::to_string(named) + "/gltf of " + scene.path.string() + ")");
    }
    // Without materials, every object using this load sets its own: the triangles
    // index this one's (never read through an instance) in place of the placeholder.
    const uint32_t material_base = materials ? uint32_t(g.materials.size()) : uint32_t(override_id);
    if (materials) {
      for (auto& m : asset.materials) g.materials.push_back(std::move(m));
    }
    Loaded l{g.meshes.size(), std::move(asset.instances), asset.uses_default_material, asset.metallic_by_default,
             asset.texcoords_not_set_0};
    for (auto& mesh : asset.meshes) {
      for (auto& id : mesh.triangle_material) id += material_base;
      g.meshes.push_back(std::move(mesh));
    }
    if (!again) {
      g.degenerate_triangles += asset.degenerate_triangles;
      for (auto& w : asset.warnings) g.warnings.push_back(std::move(w));
    }
    return loaded.emplace(std::make_pair(key, materials), std::move(l)).first;
  };
  for (size_t oi = 0; oi < scene.objects.size(); ++oi) {
    const SceneObject& obj = scene.objects[oi];
    g.object_names.push_back(obj.name);
    const std::filesystem::path& key = keys[oi];
    const int32_t override_id = obj.material.empty() ? -1 : int32_t(scene.FindMaterial(obj.material));
    auto it = load(oi, key, needs_materials[key], override_id);
    if (override_id >= 0 && it->second.texcoords_not_set_0 && g.materials[size_t(override_id)].base_color_texture) {
      it = load(oi, key, false, override_id);
    }
    if (override_id < 0 && it->second.uses_default_material) {
      // Files converted from STL or OBJ often hold no material at all.
      g.warnings.push_back("object \"" + obj.name + "\": " + obj.gltf.string() +
                           " has primitives without a material, which take glTF's default: white metal of roughness 1 "
                           "(a laser line on it is a conductor's reflection, not the diffuse line on plastic); give "
                           "the object a \"material\"");
    }
    if (override_id < 0 && !it->second.metallic_by_default.empty()) {
      // COLLADA2GLTF, Blender's first exporter and KHR_materials_common write no metallicFactor.
      g.warnings.push_back("object \"" + obj.name + "\": " + obj.gltf.string() + ": no metallicFactor in " +
                           it->second.metallic_by_default +
                           ", which glTF then makes metal (metallic 1: a laser line on it is a conductor's reflection, "
                           "not the diffuse line on plastic); give the object a \"material\" if the part is not metal");
    }
    if (override_id >= 0 && g.materials[size_t(override_id)].base_color_texture) {
      // A texture needs texture coordinates: without them every hit reads uv (0, 0).
      bool without_uv = false;
      for (const GltfInstance& gi : it->second.instances) {
        without_uv |= g.meshes[it->second.first_mesh + gi.mesh].texcoords.empty();
      }
      if (without_uv) {
        g.warnings.push_back("object \"" + obj.name + "\": " + obj.gltf.string() +
                             " has meshes without texture coordinates (TEXCOORD_0): the base_color_texture of material "
                             "\"" + obj.material + "\" is read at uv (0, 0) all over them, one colour");
      }
    }
    for (const GltfInstance& gi : it->second.instances) {
      SceneInstance inst;
      inst.mesh = it->second.first_mesh + gi.mesh;
      inst.object = oi;
      inst.world_from_mesh = obj.world_from_object * Eigen::Scaling(obj.scale) * gi.file_from_mesh;
      inst.material_override = override_id;
      inst.name = obj.name + "/" + gi.node_name;
      g.instances.push_back(std::move(inst));
    }
    if (it->second.instances.empty()) {
      g.warnings.push_back("object \"" + obj.name + "\": " + obj.gltf.string() + " holds no triangles");
    }
  }
  WarnImplausibleSizes(scene, &g);
  WarnImplausibleRig(scene.sensor, &g);
  if (scene.objects.empty() && !scene.print) {
    g.warnings.push_back("the scene has no objects: the camera sees only the environment (dark frames without one)");
  }
  if (scene.print) {
    // The printed part: one empty mesh and instance per chunk, placed by the
    // motion's world_from_gcode; PrintedPart fills the meshes over time.
    const auto& motion = std::get<GcodeMotion>(scene.motion);
    int32_t material = scene.print->material.empty() ? -1 : int32_t(scene.FindMaterial(scene.print->material));
    if (material < 0) {
      material = int32_t(g.materials.size());
      g.materials.push_back(DefaultPrintMaterial());
    }
    const size_t object = g.object_names.size();
    g.object_names.push_back("print");
    const size_t chunks = SplitPrintIntoChunks(motion.toolpath->path(), scene.print->chunk_moves).size();
    for (size_t c = 0; c < chunks; ++c) {
      Mesh mesh;
      mesh.name = "print/chunk_" + std::to_string(c);
      SceneInstance inst;
      inst.mesh = g.meshes.size();
      inst.object = object;
      inst.world_from_mesh = Eigen::Affine3d(motion.world_from_gcode.matrix());
      inst.material_override = material;
      inst.name = mesh.name;
      g.print_meshes.push_back(g.meshes.size());
      g.meshes.push_back(std::move(mesh));
      g.instances.push_back(std::move(inst));
    }
  }
  return g;
}

}  // namespace lt

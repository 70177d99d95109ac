// `lasertwin info SCENE [--json]`: loads a scene file and everything it references
// (glTF geometry, textures, the sensor rig), builds the Embree scene, and prints
// what it holds: objects, triangle and instance counts, bounds, materials, the
// sensor, motion, render and output settings, and warnings.
// Exit codes: 0 success, 2 bad input (message on stderr), 1 internal failure.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "scene/embree_scene.h"
#include "scene/printed_part.h"
#include "scene/scene_file.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {
namespace {

struct InfoArgs {
  std::string scene;
  bool json = false;
};

constexpr double kRadToDeg = 180.0 / M_PI;

// Shortest readable form of a number (up to 6 significant digits).
std::string Num(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

std::string Vec(Eigen::Vector3d v, double scale = 1.0) {
  v = (v.array().abs() < 1e-12).select(0.0, v);  // no "-1.2e-16" from rotations
  return "[" + Num(v.x() * scale) + ", " + Num(v.y() * scale) + ", " + Num(v.z() * scale) + "]";
}

nlohmann::json JsonVec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

const char* DistortionName(DistortionModel m) {
  switch (m) {
    case DistortionModel::kNone: return "none";
    case DistortionModel::kBrownConrady: return "brown_conrady";
    case DistortionModel::kFisheye: return "fisheye";
  }
  return "?";
}

// Everything `info` reports, as JSON (printed as is with --json, as text otherwise).
// The angle between the rays through the left and right edges of the image on
// the principal row, lens distortion included (barrel distortion widens it);
// the pinhole's angle when the edges lie outside the distortion model's domain.
double HorizontalFovDeg(const Camera& c) {
  const auto left = c.Unproject({-0.5, c.cy()}), right = c.Unproject({c.width() - 0.5, c.cy()});
  if (!left || !right) return 2 * std::atan(0.5 * c.width() / c.fx()) * kRadToDeg;
  return (std::atan2(-left->x(), left->z()) + std::atan2(right->x(), right->z())) * kRadToDeg;
}

nlohmann::json Describe(const SceneFile& scene, const EmbreeScene& embree) {
  const SceneGeometry& g = embree.geometry();
  nlohmann::json j;
  j["scene"] = scene.path.string();
  j["seed"] = scene.seed;

  nlohmann::json objects = nlohmann::json::array();
  for (size_t oi = 0; oi < scene.objects.size(); ++oi) {
    const SceneObject& o = scene.objects[oi];
    size_t instances = 0, triangles = 0;
    for (const auto& inst : g.instances) {
      if (inst.object == oi) {
        ++instances;
        triangles += g.meshes[inst.mesh].TriangleCount();
      }
    }
    nlohmann::json jo = {{"name", o.name}, {"gltf", o.gltf.string()}, {"instances", instances}, {"triangles", triangles},
                         {"position_m", JsonVec(o.world_from_object.translation())}};
    if (!o.material.empty()) jo["material"] = o.material;
    objects.push_back(jo);
  }
  j["objects"] = objects;

  const auto& b = embree.bounds();
  j["geometry"] = {{"meshes", g.meshes.size()},
                   {"instances", embree.instance_count()},
                   {"triangles", embree.triangle_count()},
                   {"unique_triangles", embree.unique_triangle_count()},
                   {"degenerate_triangles_dropped", embree.degenerate_triangle_count()},
                   {"render_origin_m", JsonVec(embree.render_origin())}};
  if (!b.isEmpty()) {
    j["bounds_m"] = {{"min", JsonVec(b.min())}, {"max", JsonVec(b.max())}, {"size", JsonVec(b.sizes())}};
  }

  nlohmann::json materials = nlohmann::json::array();
  // A material no triangle takes is marked, so that a change to it having no effect
  // is explained: glTF materials no placed triangle names (material libraries), scene
  // materials no object takes.
  const std::vector<bool> used = g.UsedMaterials();
  for (size_t mi = 0; mi < g.materials.size(); ++mi) {
    const Material& m = g.materials[mi];
    nlohmann::json jm = {{"name", m.name},
                         {"base_color", JsonVec(m.base_color.cast<double>())},
                         {"metallic", m.metallic},
                         {"roughness", m.roughness}};
    if (m.base_color_texture) {
      jm["base_color_texture"] = {{"name", m.base_color_texture->name},
                                  {"size", {m.base_color_texture->image.width, m.base_color_texture->image.height}}};
    }
    if (m.emissive.squaredNorm() > 0) jm["emissive"] = JsonVec(m.emissive.cast<double>());
    if (m.double_sided) jm["double_sided"] = true;
    if (m.alpha_mode != AlphaMode::kOpaque) {
      jm["alpha_mode"] = m.alpha_mode == AlphaMode::kMask ? "mask" : "blend";
      jm["alpha"] = m.alpha;
      if (m.alpha_mode == AlphaMode::kMask) jm["alpha_cutoff"] = m.alpha_cutoff;
    }
    if (m.subsurface) {
      jm["subsurface"] = {{"mean_free_path_mm", JsonVec(m.subsurface->mean_free_path_m * 1e3)},
                          {"mean_free_path_laser_mm", m.subsurface->mean_free_path_laser_m * 1e3}};
    }
    if (!used[mi]) {
      jm["unused"] = mi < scene.materials.size() ? "no object takes it" : "no triangle the scene places uses it";
    }
    materials.push_back(jm);
  }
  j["materials"] = materials;

  const SensorRig& rig = scene.sensor;
  const Camera& c = rig.camera;
  nlohmann::json cam = {{"resolution", {c.width(), c.height()}},
                        {"pixel_pitch_um", c.pixel_pitch_m() * 1e6},
                        {"fx", c.fx()},
                        {"fy", c.fy()},
                        {"cx", c.cx()},
                        {"cy", c.cy()},
                        {"focal_length_mm", c.focal_length_m() * 1e3},
                        {"f_number", c.f_number()},
                        {"distortion", DistortionName(c.distortion_model())},
                        {"horizontal_fov_deg", HorizontalFovDeg(c)}};
  if (!c.is_pinhole()) {
    const double s = c.focus_distance_m(), v = c.image_distance_m();
    cam["focus_distance_m"] = s;
    cam["field_at_focus_mm"] = {c.width() * c.pixel_pitch_m() * s / v * 1e3, c.height() * c.pixel_pitch_m() * s / v * 1e3};
  }
  nlohmann::json lasers = nlohmann::json::array();
  for (const auto& l : rig.lasers) {
    lasers.push_back({{"wavelength_nm", l.wavelength_m() * 1e9},
                      {"power_mw", l.power_w() * 1e3},
                      {"fan_angle_deg", l.params().fan_angle_rad * kRadToDeg},
                      {"sheets", l.sheet_count()},
                      {"baseline_mm", l.origin_in_cam().norm() * 1e3}});
  }
  const auto& is = rig.image_sensor;
  nlohmann::json shutter = nlohmann::json::array();
  for (const auto& f : rig.shutter.params().cycle) {
    shutter.push_back({{"label", f.label}, {"exposure_us", f.exposure_s * 1e6}, {"laser", f.laser}, {"led", f.led},
                       {"pattern", f.pattern}});
  }
  j["sensor"] = {{"camera", cam},
                 {"image_sensor",
                  {{"color_filter", ColorFilterName(is.color_filter())},
                   {"bit_depth", is.bit_depth()},
                   {"full_well_e", is.params().full_well_e},
                   {"system_gain_dn_per_e", is.SystemGain()}}},
                 {"lasers", lasers},
                 {"shutter", {{"frame_period_ms", rig.shutter.params().frame_period_s * 1e3}, {"cycle", shutter}}}};
  if (rig.led) {
    j["sensor"]["led"] = {{"area_mm2", rig.led->area_m2() * 1e6},
                          {"radiance_w_per_m2_sr", {rig.led->radiance()[0], rig.led->radiance()[1], rig.led->radiance()[2]}}};
  }
  if (rig.pattern) j["sensor"]["pattern_projector"] = {{"power_mw", rig.pattern->power_w() * 1e3}};

  const Pose world_from_cam = WorldFromCamAt(scene.motion, 0.0);
  j["motion"] = {{"type", MotionTypeName(scene.motion)},
                 {"camera_position_m", JsonVec(world_from_cam.translation())},
                 {"view_direction", JsonVec(world_from_cam.linear().col(2))},
                 {"notes", MotionNotes(scene.motion)}};
  if (scene.print) {
    const auto& motion = std::get<GcodeMotion>(scene.motion);
    std::string material;
    for (const SceneInstance& inst : g.instances) {
      if (inst.object == scene.objects.size() && inst.material_override >= 0) {
        material = g.materials.at(size_t(inst.material_override)).name;
      }
    }
    j["print"] = {{"chunks", g.print_meshes.size()},
                  {"material", material},
                  {"triangles_when_complete", PrintTrianglesWhenComplete(motion.toolpath->path(), *scene.print)},
                  {"settings", PrintSettingsToJson(*scene.print)}};
  }
  j["environment"] = ToJson(scene.environment);
  j["render"] = ToJson(scene.render);
  j["output"] = ToJson(scene.output);
  j["warnings"] = g.warnings;
  return j;
}

void PrintText(const nlohmann::json& j, std::ostream& out) {
  auto vec = [](const nlohmann::json& a, double scale = 1.0) {
    return Vec({a[0].get<double>(), a[1].get<double>(), a[2].get<double>()}, scale);
  };
  out << "scene: " << j["scene"].get<std::string>() << "  (seed " << j["seed"] << ")\n";
  out << "objects: " << j["objects"].size() << "\n";
  for (const auto& o : j["objects"]) {
    out << "  " << o["name"].get<std::string>() << ": " << o["gltf"].get<std::string>() << ", " << o["instances"]
        << " instance(s), " << o["triangles"] << " triangles";
    if (o.contains("material")) out << ", material " << o["material"].get<std::string>();
    out << "\n";
  }
  const auto& g = j["geometry"];
  out << "geometry: " << g["triangles"] << " triangles (" << g["unique_triangles"] << " unique in " << g["meshes"]
      << " meshes), " << g["instances"] << " instances, " << g["degenerate_triangles_dropped"]
      << " degenerate triangles dropped\n";
  if (j.contains("bounds_m")) {
    out << "bounds (world, mm): min " << vec(j["bounds_m"]["min"], 1e3) << " max " << vec(j["bounds_m"]["max"], 1e3)
        << " size " << vec(j["bounds_m"]["size"], 1e3) << "\n";
  } else {
    out << "bounds: empty\n";
  }
  size_t unused = 0;
  for (const auto& m : j["materials"]) unused += m.contains("unused") ? 1 : 0;
  out << "materials: " << j["materials"].size();
  if (unused > 0) out << " (" << unused << " unused)";
  out << "\n";
  for (size_t i = 0; i < j["materials"].size(); ++i) {
    const auto& m = j["materials"][i];
    out << "  " << i << " " << m["name"].get<std::string>() << ": base_color " << vec(m["base_color"]) << ", metallic "
        << Num(m["metallic"].get<double>()) << ", roughness " << Num(m["roughness"].get<double>());
    if (m.contains("base_color_texture")) {
      out << ", texture " << m["base_color_texture"]["name"].get<std::string>() << " ("
          << m["base_color_texture"]["size"][0] << "x" << m["base_color_texture"]["size"][1] << ")";
    }
    if (m.contains("emissive")) out << ", emissive " << vec(m["emissive"]) << " W/(m^2 sr)";
    if (m.contains("double_sided")) out << ", double-sided";
    if (m.contains("alpha_mode")) {
      // How the renderer reads the base colour's alpha (Material::alpha_mode).
      if (m["alpha_mode"] == "mask") {
        out << ", alpha mask (holes where alpha < " << Num(m["alpha_cutoff"].get<double>()) << ", alpha "
            << Num(m["alpha"].get<double>()) << ")";
      } else {
        out << ", alpha blend (alpha " << Num(m["alpha"].get<double>()) << " read as coverage)";
      }
    }
    if (m.contains("subsurface")) {
      out << ", subsurface mean free path " << vec(m["subsurface"]["mean_free_path_mm"]) << " mm (laser "
          << Num(m["subsurface"]["mean_free_path_laser_mm"].get<double>()) << " mm)";
    }
    if (m.contains("unused")) out << "; unused: " << m["unused"].get<std::string>();
    out << "\n";
  }
  const auto& s = j["sensor"];
  const auto& c = s["camera"];
  out << "sensor:\n  camera: " << c["resolution"][0] << "x" << c["resolution"][1] << " px, pitch "
      << Num(c["pixel_pitch_um"].get<double>()) << " um, fx " << Num(c["fx"].get<double>()) << " px, f "
      << Num(c["focal_length_mm"].get<double>()) << " mm, f/" << Num(c["f_number"].get<double>()) << ", "
      << (c.contains("focus_distance_m") ? "focused at " + Num(c["focus_distance_m"].get<double>() * 1e3) + " mm"
                                         : std::string("pinhole"))
      << ", distortion " << c["distortion"].get<std::string>() << ", horizontal FOV "
      << Num(c["horizontal_fov_deg"].get<double>()) << " deg";
  if (c.contains("field_at_focus_mm")) {
    out << ", field at focus " << Num(c["field_at_focus_mm"][0].get<double>()) << " x "
        << Num(c["field_at_focus_mm"][1].get<double>()) << " mm";
  }
  const auto& is = s["image_sensor"];
  out << "\n  image sensor: " << is["color_filter"].get<std::string>() << ", " << is["bit_depth"] << " bit, full well "
      << Num(is["full_well_e"].get<double>()) << " e-, gain " << Num(is["system_gain_dn_per_e"].get<double>())
      << " DN/e-\n";
  for (size_t i = 0; i < s["lasers"].size(); ++i) {
    const auto& l = s["lasers"][i];
    out << "  laser " << i << ": " << Num(l["wavelength_nm"].get<double>()) << " nm, "
        << Num(l["power_mw"].get<double>()) << " mW, fan " << Num(l["fan_angle_deg"].get<double>()) << " deg, "
        << l["sheets"] << " sheet(s), " << Num(l["baseline_mm"].get<double>()) << " mm from the camera\n";
  }
  if (s["lasers"].empty()) out << "  lasers: none\n";
  if (s.contains("led")) {
    out << "  led: " << Num(s["led"]["area_mm2"].get<double>()) << " mm^2, radiance "
        << vec(s["led"]["radiance_w_per_m2_sr"]) << " W/(m^2 sr)\n";
  }
  if (s.contains("pattern_projector")) {
    out << "  pattern projector: " << Num(s["pattern_projector"]["power_mw"].get<double>()) << " mW\n";
  }
  out << "  shutter: period " << Num(s["shutter"]["frame_period_ms"].get<double>()) << " ms, cycle";
  for (const auto& f : s["shutter"]["cycle"]) {
    out << " [" << f["label"].get<std::string>() << " " << Num(f["exposure_us"].get<double>()) << " us"
        << (f["laser"].get<bool>() ? " laser" : "") << (f["led"].get<bool>() ? " led" : "")
        << (f["pattern"].get<bool>() ? " pattern" : "") << "]";
  }
  out << "\n";
  const auto& mo = j["motion"];
  out << "motion: " << mo["type"].get<std::string>() << ", camera at " << vec(mo["camera_position_m"], 1e3)
      << " mm looking along " << vec(mo["view_direction"]) << "\n";
  for (const auto& n : mo["notes"]) out << "  " << n.get<std::string>() << "\n";
  if (j.contains("print")) {
    const auto& p = j["print"];
    out << "print: the part grows along the toolpath in " << p["chunks"].get<size_t>() << " chunk(s), material "
        << p["material"].get<std::string>() << ", " << p["triangles_when_complete"].get<size_t>()
        << " triangles when complete\n";
  }
  out << "environment: " << j["environment"].dump() << "\n";
  out << "render: " << j["render"].dump() << "\n";
  out << "output: " << j["output"].dump() << "\n";
  out << "warnings: " << j["warnings"].size() << "\n";
  for (const auto& w : j["warnings"]) out << "  " << w.get<std::string>() << "\n";
}

void RunInfo(const InfoArgs& args) {
  SceneFile scene = LoadSceneFile(args.scene);
  auto geometry = std::make_shared<const SceneGeometry>(LoadSceneGeometry(scene));
  EmbreeScene embree(geometry);
  nlohmann::json j = Describe(scene, embree);
  if (args.json) {
    std::cout << j.dump(2) << "\n";
  } else {
    PrintText(j, std::cout);
  }
}

void AddInfo(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  auto* cmd = app.add_subcommand("info", "Load a scene and print what it holds (geometry, materials, sensor, warnings)");
  cmd->add_option("scene", args->scene, "Scene file (JSON)")->required();
  cmd->add_flag("--json", args->json, "Print the summary as JSON");
  cmd->callback([args] { RunInfo(*args); });
}

}  // namespace

LT_REGISTER_COMMAND("info", AddInfo);

}  // namespace lt::cli

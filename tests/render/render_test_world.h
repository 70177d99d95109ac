// Small scenes built in memory for renderer tests: meshes, materials, a camera
// and laser, without files.
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>

#include "core/json_reader.h"
#include "scene/embree_scene.h"
#include "scene/scene_file.h"

namespace lt::test {

// A rectangle centred at `center` spanned by unit vectors a, b (half sizes ha, hb),
// facing a × b, as two triangles.
inline Mesh Rectangle(const Eigen::Vector3d& center, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double ha,
                      double hb, uint32_t material = 0) {
  Mesh m;
  m.name = "rectangle";
  Eigen::Vector3d n = a.cross(b).normalized();
  for (auto [sa, sb] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    m.positions.push_back((center + sa * ha * a + sb * hb * b).cast<float>());
    m.normals.push_back(n.cast<float>());
  }
  m.indices = {0, 1, 2, 0, 2, 3};
  m.triangle_material = {material, material};
  return m;
}

// An axis-aligned box with outward faces.
inline Mesh Box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, uint32_t material = 0) {
  Mesh m;
  m.name = "box";
  Eigen::Vector3d c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  auto face = [&](const Eigen::Vector3d& n, const Eigen::Vector3d& a, double ha, const Eigen::Vector3d& b,
                  double hb, double hn) {
    Mesh r = Rectangle(c + hn * n, a, b, ha, hb, material);
    if (a.cross(b).dot(n) < 0) std::swap(r.indices[1], r.indices[2]), std::swap(r.indices[4], r.indices[5]);
    uint32_t base = uint32_t(m.positions.size());
    for (size_t i = 0; i < 4; ++i) {
      m.positions.push_back(r.positions[i]);
      m.normals.push_back(n.cast<float>());
    }
    for (uint32_t i : r.indices) m.indices.push_back(base + i);
    m.triangle_material.push_back(material);
    m.triangle_material.push_back(material);
  };
  Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ();
  face(X, Y, h.y(), Z, h.z(), h.x());
  face(-X, Y, h.y(), Z, h.z(), h.x());
  face(Y, X, h.x(), Z, h.z(), h.y());
  face(-Y, X, h.x(), Z, h.z(), h.y());
  face(Z, X, h.x(), Y, h.y(), h.z());
  face(-Z, X, h.x(), Y, h.y(), h.z());
  return m;
}

inline Material Plastic(float albedo = 0.8f, float roughness = 0.5f) {
  Material m;
  m.name = "plastic";
  m.base_color = Eigen::Vector3f::Constant(albedo);
  m.metallic = 0;
  m.roughness = roughness;
  return m;
}

// A scene under construction: add meshes (each placed once), then Build().
struct World {
  SceneFile scene;
  std::shared_ptr<SceneGeometry> geometry = std::make_shared<SceneGeometry>();
  std::unique_ptr<EmbreeScene> embree;

  void Add(Mesh mesh, const Eigen::Affine3d& world_from_mesh = Eigen::Affine3d::Identity()) {
    SceneInstance inst;
    inst.mesh = geometry->meshes.size();
    inst.world_from_mesh = world_from_mesh;
    inst.name = mesh.name;
    geometry->meshes.push_back(std::move(mesh));
    geometry->instances.push_back(inst);
  }
  void Build() {
    if (geometry->materials.empty()) geometry->materials.push_back(Plastic());
    embree = std::make_unique<EmbreeScene>(geometry);
  }
};

// A floor 0.6 m square at z = floor_z and, above it at plate_z, a 0.2 m plate
// of a glTF MASK material (material 1) whose 2x1 clamped alpha texture (0, 1)
// cuts out its half at y < 0 (u runs along world y); the world is built.
inline void BuildMaskedPlateOverFloor(World& world, double plate_z, double floor_z) {
  world.Add(Rectangle({0, 0, floor_z}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.3, 0.3));
  Mesh plate = Rectangle({0, 0, plate_z}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.1, 0.1, 1);
  plate.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  world.Add(plate);
  auto texture = std::make_shared<Texture>();
  texture->image = Image<uint8_t>(2, 1, 4, 255);
  texture->image.At(0, 0, 3) = 0;
  texture->wrap_s = texture->wrap_t = WrapMode::kClampToEdge;
  Material mask = Plastic();
  mask.alpha_mode = AlphaMode::kMask;
  mask.base_color_texture = texture;
  world.geometry->materials = {Plastic(), mask};
  world.Build();
}

// A pinhole (or distorted) camera looking along +z from the world origin.
inline Camera TestCamera(int w, int h, double fx, DistortionModel model = DistortionModel::kNone,
                         BrownConradyCoeffs bc = {}) {
  CameraParams p;
  p.width = w;
  p.height = h;
  p.fx = p.fy = fx;
  p.cx = (w - 1) / 2.0;
  p.cy = (h - 1) / 2.0;
  p.pixel_pitch_m = 5e-6;
  p.f_number = 4;
  p.distortion = model;
  p.brown_conrady = bc;
  return Camera(p);
}

// A single-sheet laser `baseline` metres along camera x, its sheet spanning
// camera y (a vertical stripe), aimed at the optical axis at depth `aim_z`.
inline LaserProjector TestLaser(double baseline, double aim_z, double power_w = 5e-3,
                                double divergence_rad = 2e-3, int sheets = 1, double spacing_rad = 0) {
  LaserParams p;
  p.power_w = power_w;
  p.wavelength_m = 650e-9;
  double theta = std::atan2(baseline, aim_z);
  Pose cam_from_projector = Pose::Identity();
  cam_from_projector.linear() = (Eigen::AngleAxisd(-theta, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()))
                                    .toRotationMatrix();
  cam_from_projector.translation() = Eigen::Vector3d(baseline, 0, 0);
  p.cam_from_projector = cam_from_projector;
  p.fan_angle_rad = 60.0 * M_PI / 180.0;
  p.divergence_rad = divergence_rad;
  p.sheet_angles_rad = sheets == 1 ? std::vector<double>{0.0} : EvenSheetAngles(sheets, spacing_rad);
  p.sheet_power = std::vector<double>(size_t(sheets), 1.0);
  return LaserProjector(p);
}

// The scanner sliding along the camera's x axis at `speed_m_s` from t = 0 for
// 10 ms: a pose list written to dir/poses.csv ("time_origin": "file").
inline Motion SlidingAlongX(const std::filesystem::path& dir, double speed_m_s) {
  std::filesystem::create_directories(dir);
  std::ofstream csv(dir / "poses.csv");
  csv.precision(17);
  csv << "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.01," << 0.01 * speed_m_s << ",0,0,1,0,0,0\n";
  csv.close();
  auto doc = json::Document::Parse(R"({"type": "pose_list", "file": "poses.csv", "time_origin": "file"})",
                                   "scene.json", dir);
  return ParseMotion(doc.Root());
}

}  // namespace lt::test

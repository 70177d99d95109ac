// Generates the geometry of the demo scene (scenes/demo): a 3D-printed slot test
// part and the print bed it lies on, as binary glTF in metres.
//
//   make_demo_scene [output_folder]      (default: scenes/demo)
//
// The test part is a plate with 16 slots, 0.2 to 1.7 mm wide in 0.1 mm steps
// (like a feeler gauge), cut across its width: a comb-shaped profile in the x-z
// plane extruded along y. It is centred on x = y = 0 and stands on z = 0. The
// print bed is a 150 x 150 x 2 mm slab whose top is z = 0, with a base-colour
// texture (a 10 mm grid, as printed on many beds).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <vector>

#include "core/image.h"
#include "core/image_io.h"
#include "scene/gltf_writer.h"

namespace {

// Test part dimensions (metres).
constexpr int kSlots = 16;
constexpr double kNarrowest = 0.2e-3, kStep = 0.1e-3;  // slot widths 0.2 .. 1.7 mm
constexpr double kLand = 1.8e-3;                       // material between slots
constexpr double kMargin = 4.0e-3;                     // material before the first / after the last slot
constexpr double kWidth = 20.0e-3;                     // along y (the slots' length)
constexpr double kThickness = 3.0e-3;                  // plate height
constexpr double kSlotDepth = 1.0e-3;

// Print bed (metres).
constexpr double kBedSize = 150e-3, kBedThickness = 2e-3;

// Flat-shaded triangle soup with per-corner normals and texture coordinates.
struct Soup {
  std::vector<float> positions, normals, texcoords;
  std::vector<uint32_t> indices;

  // A planar quad a-b-c-d (counter-clockwise seen from the side `normal` points to).
  void Quad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d,
            const Eigen::Vector3d& normal, const std::array<Eigen::Vector2d, 4>* uv = nullptr) {
    if ((b - a).cross(c - a).dot(normal) <= 0) {
      std::cerr << "make_demo_scene: quad wound against its normal\n";
      std::exit(1);
    }
    const uint32_t base = uint32_t(positions.size() / 3);
    const Eigen::Vector3d corners[4] = {a, b, c, d};
    for (int k = 0; k < 4; ++k) {
      for (int i = 0; i < 3; ++i) {
        positions.push_back(float(corners[k][i]));
        normals.push_back(float(normal[i]));
      }
      texcoords.push_back(uv ? float((*uv)[size_t(k)].x()) : 0.0f);
      texcoords.push_back(uv ? float((*uv)[size_t(k)].y()) : 0.0f);
    }
    indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }

  // An axis-aligned rectangle in the plane `axis` = value, spanning [lo, hi] in
  // the two other axes, facing +axis (sign > 0) or -axis.
  void Rect(int axis, double value, Eigen::Vector2d lo, Eigen::Vector2d hi, int sign) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    auto point = [&](double pu, double pv) {
      Eigen::Vector3d p;
      p[axis] = value;
      p[u] = pu;
      p[v] = pv;
      return p;
    };
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    n[axis] = sign;
    Eigen::Vector3d a = point(lo.x(), lo.y()), b = point(hi.x(), lo.y()), c = point(hi.x(), hi.y()),
                    d = point(lo.x(), hi.y());
    if (sign > 0) {
      Quad(a, b, c, d, n);
    } else {
      Quad(a, d, c, b, n);
    }
  }
};

// The comb profile: x breakpoints and, per region between them, whether it is a slot.
struct Profile {
  std::vector<double> x;
  std::vector<bool> slot;
};

Profile TestPartProfile() {
  double length = 2 * kMargin + (kSlots - 1) * kLand;
  for (int i = 0; i < kSlots; ++i) length += kNarrowest + i * kStep;
  Profile p;
  double x = -length / 2;
  p.x.push_back(x);
  x += kMargin;
  p.x.push_back(x);
  p.slot.push_back(false);
  for (int i = 0; i < kSlots; ++i) {
    x += kNarrowest + i * kStep;
    p.x.push_back(x);
    p.slot.push_back(true);
    x += i + 1 < kSlots ? kLand : kMargin;
    p.x.push_back(x);
    p.slot.push_back(false);
  }
  return p;
}

// A watertight, flat-shaded mesh of the slotted plate (no T-junctions: caps and
// end faces are split at the slot-bottom height).
Soup TestPart() {
  const Profile p = TestPartProfile();
  const double y0 = -kWidth / 2, y1 = kWidth / 2, H = kThickness, B = kThickness - kSlotDepth;
  Soup s;
  for (size_t r = 0; r + 1 < p.x.size(); ++r) {
    const double xa = p.x[r], xb = p.x[r + 1];
    const double top = p.slot[r] ? B : H;
    s.Rect(2, top, {xa, y0}, {xb, y1}, +1);  // top or slot bottom (axes x, y)
    s.Rect(2, 0.0, {xa, y0}, {xb, y1}, -1);  // underside
    // Side caps (plane y = const, axes z, x): lower part, and the land's upper part.
    s.Rect(1, y0, {0.0, xa}, {B, xb}, -1);
    s.Rect(1, y1, {0.0, xa}, {B, xb}, +1);
    if (!p.slot[r]) {
      s.Rect(1, y0, {B, xa}, {H, xb}, -1);
      s.Rect(1, y1, {B, xa}, {H, xb}, +1);
    }
  }
  // Slot walls (plane x = const, axes y, z), facing into the slot.
  for (size_t r = 0; r + 1 < p.x.size(); ++r) {
    if (!p.slot[r]) continue;
    s.Rect(0, p.x[r], {y0, B}, {y1, H}, +1);
    s.Rect(0, p.x[r + 1], {y0, B}, {y1, H}, -1);
  }
  // End faces, split at the slot-bottom height.
  for (double z : {0.0, B}) {
    double z1 = z == 0.0 ? B : H;
    s.Rect(0, p.x.front(), {y0, z}, {y1, z1}, -1);
    s.Rect(0, p.x.back(), {y0, z}, {y1, z1}, +1);
  }
  return s;
}

Soup PrintBed() {
  const double h = kBedSize / 2, z0 = -kBedThickness;
  Soup s;
  // Top with texture coordinates: u along +x, v along -y (image top at +y).
  const std::array<Eigen::Vector2d, 4> uv = {Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 1), Eigen::Vector2d(1, 0),
                                             Eigen::Vector2d(0, 0)};
  s.Quad({-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}, {0, 0, 1}, &uv);
  s.Rect(2, z0, {-h, -h}, {h, h}, -1);
  s.Rect(0, -h, {-h, z0}, {h, 0}, -1);
  s.Rect(0, h, {-h, z0}, {h, 0}, +1);
  s.Rect(1, -h, {z0, -h}, {0, h}, -1);
  s.Rect(1, h, {z0, -h}, {0, h}, +1);
  return s;
}

// The bed's texture: dark bronze (a textured PEI sheet) with a lighter line
// every 10 mm. 300 x 300 pixels for 150 mm (0.5 mm per pixel).
std::vector<uint8_t> BedTexturePng(const std::filesystem::path& scratch) {
  const int n = 300;
  lt::Image<uint8_t> img(n, n, 3);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      bool line = x % 20 == 0 || y % 20 == 0;
      uint8_t rgb[3] = {uint8_t(line ? 150 : 92), uint8_t(line ? 128 : 70), uint8_t(line ? 90 : 38)};
      for (int c = 0; c < 3; ++c) img.At(x, y, c) = rgb[c];
    }
  }
  lt::WriteImage(scratch, img);
  std::ifstream in(scratch, std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
  std::filesystem::remove(scratch);
  return bytes;
}

void Write(const Soup& s, const std::string& name, lt::GltfBuilder& b, int material, bool texcoords) {
  int mesh = b.AddTriangleMesh(name, s.positions, s.normals, texcoords ? s.texcoords : std::vector<float>{},
                               s.indices, material);
  b.AddNode(name, mesh);
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path out = argc > 1 ? argv[1] : "scenes/demo";
  std::filesystem::create_directories(out);

  lt::GltfBuilder part;
  // The file's own material (a generic grey plastic); the scene file overrides it with PLA.
  int plastic = part.AddMaterial("plastic", {0.7, 0.7, 0.7, 1}, 0.0, 0.5);
  Write(TestPart(), "slot_test_part", part, plastic, false);
  part.WriteGlb(out / "test_part.glb");

  lt::GltfBuilder bed;
  std::vector<uint8_t> png = BedTexturePng(out / "bed_texture_tmp.png");
  int view = bed.AddBufferView(png.data(), png.size());
  bed.json()["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}, {"name", "bed_grid"}}};
  bed.json()["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
  bed.json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
  int pei = bed.AddMaterial("textured_pei", {1, 1, 1, 1}, 0.0, 0.6);
  bed.json()["materials"][size_t(pei)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  Write(PrintBed(), "print_bed", bed, pei, true);
  bed.WriteGlb(out / "print_bed.glb");

  const Profile p = TestPartProfile();
  std::cout << "wrote " << (out / "test_part.glb").string() << " (" << TestPart().indices.size() / 3
            << " triangles, " << (p.x.back() - p.x.front()) * 1e3 << " x " << kWidth * 1e3 << " x "
            << kThickness * 1e3 << " mm) and " << (out / "print_bed.glb").string() << "\n";
  for (size_t r = 0; r + 1 < p.x.size(); ++r) {
    if (p.slot[r]) {
      std::cout << "  slot " << std::round((p.x[r + 1] - p.x[r]) * 1e4) / 10 << " mm at x = ["
                << p.x[r] * 1e3 << ", " << p.x[r + 1] * 1e3 << "] mm\n";
    }
  }
  return 0;
}

// Generates the sharp-edge test part of the extraction experiment
// (docs/experiments.md, "Extraction at sharp edges"; scenes/sharp_edges):
//
//   make_edge_part [output_folder]      (default: scenes/sharp_edges)
//
// A profile in the x-z plane extruded 20 mm along y, standing on z = 0: a flat
// land, two steps up (1 mm each) and one down, a 90-degree roof ridge 3 mm
// high, a 90-degree V-groove 1 mm deep, and a step up at the end, so that a
// laser stripe running along x crosses depth discontinuities (steps), convex
// and concave creases (ridge, groove) and flat regions. Flat-shaded, metres.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <vector>

#include "scene/gltf_writer.h"

namespace {

constexpr double kLength = 20e-3;  // along y

// Profile breakpoints (x, z) in mm, left to right. Vertical segments are steps.
const std::vector<Eigen::Vector2d> kProfileMm = {
    {-20, 2},  {-14, 2},   {-14, 3},   {-10, 3}, {-10, 4}, {-6, 4}, {-6, 2.5}, {-2, 2.5}, {1, 5.5},
    {4, 2.5},  {8, 2.5},   {9, 1.5},   {10, 2.5}, {14, 2.5}, {14, 4}, {20, 4}};

struct Soup {
  std::vector<float> positions, normals;
  std::vector<uint32_t> indices;
  void Tri(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-15) return;
    n.normalize();
    uint32_t base = uint32_t(positions.size() / 3);
    for (const Eigen::Vector3d* p : {&a, &b, &c})
      for (int i = 0; i < 3; ++i) {
        positions.push_back(float((*p)[i]));
        normals.push_back(float(n[i]));
      }
    indices.insert(indices.end(), {base, base + 1, base + 2});
  }
  // Quad a-b-c-d, counter-clockwise seen from outside.
  void Quad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
    Tri(a, b, c);
    Tri(a, c, d);
  }
};

Soup EdgePart() {
  Soup s;
  const double y0 = -kLength / 2, y1 = kLength / 2;
  std::vector<Eigen::Vector2d> p;
  for (const Eigen::Vector2d& q : kProfileMm) p.push_back(q * 1e-3);
  auto P = [](double x, double y, double z) { return Eigen::Vector3d(x, y, z); };
  for (size_t i = 0; i + 1 < p.size(); ++i) {
    const Eigen::Vector2d &a = p[i], &b = p[i + 1];
    // The profile's surface strip (outward: the profile runs left to right, up is outside).
    s.Quad(P(a.x(), y0, a.y()), P(b.x(), y0, b.y()), P(b.x(), y1, b.y()), P(a.x(), y1, a.y()));
    // Side caps: the trapezoid under the segment, on y = y0 (facing -y) and y = y1 (facing +y).
    if (b.x() > a.x()) {
      s.Quad(P(a.x(), y0, 0), P(b.x(), y0, 0), P(b.x(), y0, b.y()), P(a.x(), y0, a.y()));
      s.Quad(P(b.x(), y1, 0), P(a.x(), y1, 0), P(a.x(), y1, a.y()), P(b.x(), y1, b.y()));
    }
  }
  const Eigen::Vector2d &first = p.front(), &last = p.back();
  s.Quad(P(first.x(), y0, 0), P(first.x(), y0, first.y()), P(first.x(), y1, first.y()), P(first.x(), y1, 0));
  s.Quad(P(last.x(), y1, 0), P(last.x(), y1, last.y()), P(last.x(), y0, last.y()), P(last.x(), y0, 0));
  s.Quad(P(first.x(), y1, 0), P(last.x(), y1, 0), P(last.x(), y0, 0), P(first.x(), y0, 0));  // underside
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path out = argc > 1 ? argv[1] : "scenes/sharp_edges";
  std::filesystem::create_directories(out);
  lt::GltfBuilder b;
  int plastic = b.AddMaterial("plastic", {0.7, 0.7, 0.7, 1}, 0.0, 0.5);
  Soup s = EdgePart();
  int mesh = b.AddTriangleMesh("edge_part", s.positions, s.normals, {}, s.indices, plastic);
  b.AddNode("edge_part", mesh);
  b.WriteGlb(out / "edge_part.glb");
  std::cout << "wrote " << (out / "edge_part.glb").string() << " (" << s.indices.size() / 3 << " triangles)\n";
  return 0;
}

// Ground-truth stripe centres on curved, tessellated and awkward geometry,
// against the independent reference of stripe_reference.h (sheet x triangle
// segments projected through the camera model, row crossings by bisection,
// brute-force visibility and shadow tests): every reference crossing must be
// found and every centre must be a reference crossing, to 1e-3 px.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "stripe_reference.h"

namespace lt {
namespace {

using test::World;

constexpr double kTolPx = 1e-3;

// A grid surface f(a, b), a in [0, 1] over na cells, b in [0, 1] over nb cells.
Mesh Grid(int na, int nb, const std::function<Eigen::Vector3d(double, double)>& f, const std::string& name) {
  Mesh m;
  m.name = name;
  for (int j = 0; j <= nb; ++j) {
    for (int i = 0; i <= na; ++i) {
      m.positions.push_back(f(double(i) / na, double(j) / nb).cast<float>());
      m.normals.push_back(Eigen::Vector3f::UnitZ());  // shading normals are not used here
    }
  }
  for (int j = 0; j < nb; ++j) {
    for (int i = 0; i < na; ++i) {
      const uint32_t a = uint32_t(j * (na + 1) + i), b = a + 1, c = a + uint32_t(na + 1), d = c + 1;
      for (uint32_t k : {a, b, d, a, d, c}) m.indices.push_back(k);
      m.triangle_material.push_back(0);
      m.triangle_material.push_back(0);
    }
  }
  return m;
}

// A tube of radius r about an axis through c along unit `axis` (length len), n facets.
Mesh Cylinder(const Eigen::Vector3d& c, const Eigen::Vector3d& axis, double r, double len, int n) {
  const Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  return Grid(
      n, 1,
      [&](double a, double b) {
        const double phi = 2 * M_PI * a;
        return Eigen::Vector3d(c + (b - 0.5) * len * axis + r * (std::cos(phi) * e1 + std::sin(phi) * e2));
      },
      "cylinder");
}

// A UV sphere: n_lon x n_lat facets.
Mesh Sphere(const Eigen::Vector3d& c, double r, int n_lon, int n_lat) {
  return Grid(
      n_lon, n_lat,
      [&](double a, double b) {
        const double phi = 2 * M_PI * a, theta = M_PI * b;
        return Eigen::Vector3d(c + r * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                                       std::sin(theta) * std::sin(phi), std::cos(theta)));
      },
      "sphere");
}

// Printed beads: `count` half-cylinders of radius r along x, side by side in y
// (spacing), their tops toward -z, standing on the plane z = 0 (mesh frame).
Mesh Beads(int count, double r, double spacing, double len, int n) {
  Mesh all;
  all.name = "beads";
  for (int i = 0; i < count; ++i) {
    const double y0 = (i - 0.5 * (count - 1)) * spacing;
    Mesh b = Grid(
        n, 1,
        [&](double a, double t) {
          const double phi = M_PI * a;  // 0..pi: from +y over the top (-z) to -y
          return Eigen::Vector3d((t - 0.5) * len, y0 + r * std::cos(phi), -r * std::sin(phi));
        },
        "bead");
    const uint32_t base = uint32_t(all.positions.size());
    all.positions.insert(all.positions.end(), b.positions.begin(), b.positions.end());
    all.normals.insert(all.normals.end(), b.normals.begin(), b.normals.end());
    for (uint32_t k : b.indices) all.indices.push_back(base + k);
    all.triangle_material.insert(all.triangle_material.end(), b.triangle_material.begin(), b.triangle_material.end());
  }
  return all;
}

Mesh Floor(double z) {
  return test::Rectangle({0, 0, z}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.2, 0.2);
}

Camera StrongBrownConrady() {
  BrownConradyCoeffs bc;
  bc.k1 = -0.3;
  bc.k2 = 0.1;
  bc.p1 = 0.002;
  bc.p2 = -0.002;
  bc.k3 = -0.01;
  return test::TestCamera(160, 120, 150, DistortionModel::kBrownConrady, bc);
}

Camera Fisheye() {
  Camera pin = test::TestCamera(160, 120, 110);
  CameraParams p = pin.params();
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {0.05, -0.01, 0.002, -0.0003};
  return Camera(p);
}

struct Case {
  std::string name;
  std::function<void(World&)> build;
  double laser_y = 0;  // the projector's offset along camera y (m)
};

// The rig turned a quarter turn about the optical axis: the projector 3 cm
// along camera y, its sheet spanning camera x (stripes along the rows, scanned
// by columns).
LaserProjector QuarterTurned(const LaserProjector& laser) {
  LaserParams p = laser.params();
  Pose turn = Pose::Identity();
  turn.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.cam_from_projector = turn * p.cam_from_projector;
  return LaserProjector(p);
}

// test::TestLaser moved along camera y by `y`.
LaserProjector Shifted(const LaserProjector& laser, double y) {
  LaserParams p = laser.params();
  p.cam_from_projector.translation().y() = y;
  return LaserProjector(p);
}

// Runs one case with each camera and rig; prints and checks the comparison.
// Returns the comparison of the last run for case-specific checks.
test::RefComparison Check(const Case& c, const Camera& cam, const std::vector<LaserProjector>& lasers,
                          const std::string& cam_name, const Pose& world_from_cam = Pose::Identity(),
                          const Pose& turn = Pose::Identity()) {
  World world;
  c.build(world);  // in the camera frame (turned with the rig), placed in the world as the camera is
  for (SceneInstance& inst : world.geometry->instances) {
    inst.world_from_mesh = world_from_cam * turn * inst.world_from_mesh;
  }
  world.Build();
  const ScanAxis axis = ChooseScanAxis(lasers);
  const auto centers = ComputeStripeCenters(*world.embree, cam, lasers, world_from_cam, axis);
  test::RefDropped dropped;
  const test::RefStripe ref = test::ReferenceStripe(world, cam, lasers, world_from_cam, &dropped, axis);
  test::RefComparison r = test::CompareWithReference(ref, centers, kTolPx, axis);
  r.dropped = dropped;
  std::printf("%-20s %-8s planes %d: reference %4d (ambiguous %2d, rows with two %3d; left out: facing away %4d, "
              "hidden %3d, shadowed %3d) found %4d missed %2d (paired %2d) extra %2d max|du| %.1e px\n",
              c.name.c_str(), cam_name.c_str(), PlaneCount(lasers), r.reference, r.ambiguous, r.rows_with_two,
              dropped.facing, dropped.hidden, dropped.shadow, r.found, r.missed, r.missed_paired, r.extra, r.max_du);
  for (const auto& w : r.missed_where) std::printf("  missed %s\n", w.c_str());
  for (const auto& w : r.extra_where) std::printf("  extra  %s\n", w.c_str());
  return r;
}

std::vector<Case> Cases() {
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY();
  std::vector<Case> cases;
  cases.push_back({"cylinder-along-rows", [=](World& w) {
                     w.Add(Floor(0.125));
                     w.Add(Cylinder({0, 0.004, 0.11}, X, 0.012, 0.08, 24));
                   }});
  cases.push_back({"cylinder-along-cols", [=](World& w) {
                     w.Add(Floor(0.125));
                     const Eigen::Vector3d axis = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) * Y;
                     w.Add(Cylinder({0.002, 0, 0.11}, axis, 0.01, 0.06, 20));
                   }});
  for (int k = 0; k < 6; ++k) {
    // The sheet cuts a cap 4 mm deep off a 10 mm sphere above the optical axis,
    // the projector level with it: the lit half of the cap's rim is an arc
    // whose top (its tangent to a row, near row 10) lies inside the arc, with
    // two crossings on the rows below it. Moved down by k/6 of a pixel, so
    // that on some rows both fall between the same two pixel centres.
    const double dy = k / 6.0 * 0.09 / 150;
    cases.push_back({"sphere+" + std::to_string(k) + "/6px", [=](World& w) {
                       w.Add(Floor(0.13));
                       w.Add(Sphere({0.0088, -0.021 + dy, 0.0917}, 0.01, 32, 16));
                     }, -0.02});
  }
  cases.push_back({"beads", [=](World& w) {
                     // Eight beads of radius 2 mm at 3 mm spacing on a plate, turned 46
                     // degrees about z and tilted 57 about x and 34 about y: the stripe
                     // crosses them obliquely, their valleys shadowed from the projector
                     // and hidden from the camera.
                     Eigen::Affine3d place = Eigen::Affine3d::Identity();
                     place.translate(Eigen::Vector3d(0, 0, 0.11));
                     place.rotate(Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(1.0, X) *
                                  Eigen::AngleAxisd(0.6, Y));
                     Mesh floor = test::Rectangle({0, 0, 0}, Y, X, 0.04, 0.04);
                     w.Add(floor, place);
                     w.Add(Beads(8, 0.002, 0.003, 0.06, 10), place);
                   }});
  cases.push_back({"concave-corner", [=](World& w) {
                     // Two walls meeting along a line parallel to x at y = 0.003, z = 0.12.
                     const Eigen::Vector3d up = Eigen::Vector3d(0, -1, -1).normalized(),
                                           down = Eigen::Vector3d(0, 1, -1).normalized();
                     w.Add(test::Rectangle(Eigen::Vector3d(0, 0.003, 0.12) + 0.02 * up, X, up, 0.03, 0.02));
                     w.Add(test::Rectangle(Eigen::Vector3d(0, 0.003, 0.12) + 0.02 * down, X, down, 0.03, 0.02));
                   }});
  // A 0.3 mm fin on a floor, 2 mm left of the optical axis and 0.105 m deep:
  // turned 2 degrees about y (its lit face 3.0 degrees off the view ray), and
  // turned so that its lit face (normal n, at n.p = e from the camera centre)
  // is 0.3, 0.05 and 0 degrees off the view ray at the fin's distance r
  // (e = -r sin(deg)): there the face and the top are seen over less than a
  // pixel, on many rows wholly between two pixel centres on the floor, a
  // sliver no pixel centre sees. At 0 degrees the face's plane holds the
  // camera centre: only the top is seen.
  const double r = std::hypot(0.002, 0.105), phi = std::atan2(0.002, 0.105);
  auto lit_face_off = [&](double deg) { return std::asin((r * std::sin(deg * M_PI / 180) + 0.00015) / r) - phi; };
  for (const auto& [name, turn] : std::vector<std::pair<std::string, double>>{{"fin-edge-on", 2 * M_PI / 180},
                                                                                {"fin-0.3deg", lit_face_off(0.3)},
                                                                                {"fin-0.05deg", lit_face_off(0.05)},
                                                                                {"fin-0deg", lit_face_off(0)}}) {
    cases.push_back({name, [=, turn = turn](World& w) {
                       w.Add(Floor(0.12));
                       Eigen::Affine3d place = Eigen::Affine3d::Identity();
                       place.translate(Eigen::Vector3d(-0.002, 0, 0.105));
                       place.rotate(Eigen::AngleAxisd(turn, Y));
                       w.Add(test::Box({-0.00015, -0.015, -0.015}, {0.00015, 0.015, 0.015}), place);
                     }});
  }
  return cases;
}

// The sheet meets a plane at 87 and at 89.5 degrees from its normal.
Case Grazing(double incidence_deg) {
  return {"grazing-" + std::to_string(int(incidence_deg * 10)), [=](World& w) {
            const Eigen::Vector3d aim(0, 0, 0.1), laser_o(0.03, 0, 0);
            const Eigen::Vector3d dir = (aim - laser_o).normalized();
            const Eigen::Vector3d n0(-dir.z(), 0, dir.x());  // contains the central ray; faces the camera
            const double g = (90 - incidence_deg) * M_PI / 180;
            const Eigen::Vector3d n = std::cos(g) * n0 - std::sin(g) * dir;
            const Eigen::Vector3d a = Eigen::Vector3d::UnitY(), b = n.cross(a);
            w.Add(test::Rectangle(aim, a, b, 0.03, 0.03));
          }};
}

class StripeTruthCurved : public ::testing::TestWithParam<int> {};

TEST_P(StripeTruthCurved, EveryReferenceCrossingFoundAndNoOther) {
  std::vector<Case> cases = Cases();
  cases.push_back(Grazing(87));
  cases.push_back(Grazing(89.5));
  ASSERT_EQ(cases.size(), 16u);
  const Case& c = cases[size_t(GetParam())];
  const std::vector<LaserProjector> one = {Shifted(test::TestLaser(0.03, 0.1), c.laser_y)};
  const std::vector<LaserProjector> doe = {
      Shifted(test::TestLaser(0.03, 0.1, 5e-3, 2e-3, 5, 2.5 * M_PI / 180), c.laser_y)};
  struct Run {
    std::string name;
    Camera cam;
    const std::vector<LaserProjector>* lasers;
  };
  const std::vector<Run> runs = {{"pinhole", test::TestCamera(160, 120, 150), &one},
                                 {"brown", StrongBrownConrady(), &one},
                                 {"fisheye", Fisheye(), &one},
                                 {"doe5", test::TestCamera(160, 120, 150), &doe}};
  // The pinhole run again with the scanner 5 m from the world origin, turned.
  Pose posed = Pose::Identity();
  posed.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  posed.translation() = Eigen::Vector3d(5, -3, 2);
  for (const Run& run : runs) {
    const test::RefComparison r = Check(c, run.cam, *run.lasers, run.name);
    EXPECT_GT(r.reference, 20) << c.name << " " << run.name;
    EXPECT_EQ(r.missed, 0) << c.name << " " << run.name;
    EXPECT_EQ(r.extra, 0) << c.name << " " << run.name;
    EXPECT_LT(r.max_du, kTolPx) << c.name << " " << run.name;
  }
  // And with the rig and the scene turned a quarter turn about the optical
  // axis (Brown-Conrady camera): the stripes run along the rows and are
  // scanned by columns.
  Pose turn = Pose::Identity();
  turn.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const std::vector<LaserProjector> turned = {QuarterTurned(one[0])};
  ASSERT_EQ(ChooseScanAxis(turned), ScanAxis::kCols);
  const test::RefComparison t = Check(c, runs[1].cam, turned, "cols", Pose::Identity(), turn);
  EXPECT_GT(t.reference, 20) << c.name << " cols";
  EXPECT_EQ(t.missed, 0) << c.name << " cols";
  EXPECT_EQ(t.extra, 0) << c.name << " cols";
  EXPECT_LT(t.max_du, kTolPx) << c.name << " cols";
  const test::RefComparison r = Check(c, runs[0].cam, one, "posed", posed);
  // What the cases are for: the arcs turning back, the valleys.
  if (c.name.rfind("sphere", 0) == 0) {
    EXPECT_GE(r.rows_with_two, 8) << c.name;
  }
  if (c.name == "beads" || c.name == "fin-edge-on") {
    EXPECT_GE(std::min(r.dropped.hidden, r.dropped.shadow), 20) << c.name;
  }
  EXPECT_GT(r.reference, 20) << c.name << " posed";
  EXPECT_EQ(r.missed, 0) << c.name << " posed";
  EXPECT_EQ(r.extra, 0) << c.name << " posed";
  EXPECT_LT(r.max_du, kTolPx) << c.name << " posed";
}

INSTANTIATE_TEST_SUITE_P(Shapes, StripeTruthCurved, ::testing::Range(0, 16));

}  // namespace
}  // namespace lt

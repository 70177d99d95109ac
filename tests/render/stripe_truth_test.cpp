// Ground-truth stripe centres against closed form: the stripe on a plane is the
// line where the surface plane meets the laser plane; its centre on row v is the
// point of that line whose projection (through the camera model, with
// distortion) lands on row v, found here by root finding on the forward
// projection alone (no ray casts). The renderer's centres must agree to 1e-3 px.
#include <gtest/gtest.h>

#include <map>

#include "render/stripe_truth.h"
#include "render_test_world.h"

namespace lt {
namespace {

using test::World;

struct PlaneRect {
  Eigen::Vector3d c, a, b;  // centre, unit edge directions
  double ha, hb;
  Eigen::Vector3d n() const { return a.cross(b).normalized(); }
};

// Point of the line X0 + s L whose projection has image coordinate `coord` (index
// 1 = row v) equal to value; nullopt when none in [-smax, smax].
std::optional<Eigen::Vector3d> SolveOnLine(const Camera& cam, const Eigen::Vector3d& X0, const Eigen::Vector3d& L,
                                           double value, double smax) {
  auto f = [&](double s) -> std::optional<double> {
    auto px = cam.Project(X0 + s * L);
    if (!px) return std::nullopt;
    return px->y() - value;
  };
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    double s0 = -smax + 2 * smax * i / n, s1 = -smax + 2 * smax * (i + 1) / n;
    auto f0 = f(s0), f1 = f(s1);
    if (!f0 || !f1 || (*f0 > 0) == (*f1 > 0)) continue;
    for (int it = 0; it < 200; ++it) {
      double sm = 0.5 * (s0 + s1);
      auto fm = f(sm);
      if (!fm) return std::nullopt;
      if ((*fm > 0) == (*f0 > 0)) s0 = sm, f0 = fm; else s1 = sm;
    }
    return X0 + 0.5 * (s0 + s1) * L;
  }
  return std::nullopt;
}

// The laser plane meets the rectangle's plane along a line: a point and direction.
std::pair<Eigen::Vector3d, Eigen::Vector3d> PlaneLine(const Plane& laser, const PlaneRect& r) {
  Eigen::Vector3d m = r.n();
  Eigen::Vector3d L = m.cross(laser.n).normalized();
  // Point on both planes closest to r.c: solve [m; n; L] X = [m.c; -d; L.c].
  Eigen::Matrix3d A;
  A.row(0) = m;
  A.row(1) = laser.n;
  A.row(2) = L;
  Eigen::Vector3d X0 = A.colPivHouseholderQr().solve(Eigen::Vector3d(m.dot(r.c), -laser.d, L.dot(r.c)));
  return {X0, L};
}

Camera DistortedCamera() {
  BrownConradyCoeffs bc;
  bc.k1 = -0.25;
  bc.k2 = 0.08;
  bc.p1 = 0.001;
  bc.p2 = -0.0015;
  bc.k3 = -0.01;
  return test::TestCamera(200, 150, 180, DistortionModel::kBrownConrady, bc);
}

class StripeTruthPlane : public ::testing::TestWithParam<bool> {};

TEST_P(StripeTruthPlane, TiltedPlaneMatchesClosedForm) {
  const bool distorted = GetParam();
  Camera cam = distorted ? DistortedCamera() : test::TestCamera(200, 150, 180);
  LaserProjector laser = test::TestLaser(0.03, 0.1);
  // A plane 0.1 m away, tilted 35 degrees about y and 20 degrees about x.
  Eigen::Matrix3d R = (Eigen::AngleAxisd(35 * M_PI / 180, Eigen::Vector3d::UnitY()) *
                       Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitX()))
                          .toRotationMatrix();
  PlaneRect rect{Eigen::Vector3d(0, 0, 0.1), R.col(0), R.col(1), 0.2, 0.2};
  if (rect.n().z() > 0) std::swap(rect.a, rect.b);  // face the camera
  World world;
  world.Add(test::Rectangle(rect.c, rect.a, rect.b, rect.ha, rect.hb));
  world.Build();
  std::vector<LaserProjector> lasers = {laser};
  ASSERT_EQ(ChooseScanAxis(lasers), ScanAxis::kRows);
  auto centers = ComputeStripeCenters(*world.embree, cam, lasers, Pose::Identity(), ScanAxis::kRows);
  auto [X0, L] = PlaneLine(laser.SheetPlane(0), rect);
  int compared = 0;
  double worst = 0;
  for (const auto& c : centers) {
    auto X = SolveOnLine(cam, X0, L, c.v, 0.5);
    ASSERT_TRUE(X.has_value()) << "row " << c.v;
    double u = cam.Project(*X)->x();
    worst = std::max(worst, std::abs(u - c.u));
    // Mesh vertices are float: the rendered plane is the analytic one to ~0.2 m * 2^-24 = 1.2e-8 m.
    EXPECT_LT((c.p_cam - *X).norm(), 5e-8);
    ++compared;
  }
  EXPECT_EQ(compared, cam.height());  // the stripe crosses every row
  EXPECT_LT(worst, 1e-3) << "largest deviation from the closed form (px)";
  EXPECT_LT(worst, 1e-4) << "the refinement targets 1e-4 px";
}

INSTANTIATE_TEST_SUITE_P(WithAndWithoutDistortion, StripeTruthPlane, ::testing::Values(false, true));

// Segment p->q passes through the open box (deeper than margin)?
// Segment p->q passes through the box grown by -margin, ignoring 1 um at each end
// (the end points may lie on the box's surface)?
bool SegmentHitsBox(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& lo,
                    const Eigen::Vector3d& hi, double margin) {
  Eigen::Vector3d d = q - p;
  double t0 = 1e-6 / d.norm(), t1 = 1 - 1e-6 / d.norm();
  for (int k = 0; k < 3; ++k) {
    double l = lo[k] + margin, h = hi[k] - margin;
    if (std::abs(d[k]) < 1e-300) {
      if (p[k] <= l || p[k] >= h) return false;
      continue;
    }
    double a = (l - p[k]) / d[k], b = (h - p[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 >= t1) return false;
  }
  return true;
}

// The stripe centres of a box on a floor (or floating, with nothing behind it)
// against the closed form; returns, per face, the centres expected on it (face 0
// the floor).
std::map<size_t, int> ExpectBoxMatchesClosedForm(const Camera& cam, const LaserProjector& laser,
                                                 const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                                 const std::string& what, bool with_floor = true) {
  const double floor_z = 0.12;
  World world;
  if (with_floor) {
    world.Add(test::Rectangle({0, 0, floor_z}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.3, 0.3));
  }
  world.Add(test::Box(lo, hi));
  world.Build();
  std::vector<LaserProjector> lasers = {laser};
  auto centers = ComputeStripeCenters(*world.embree, cam, lasers, Pose::Identity(), ScanAxis::kRows);
  // Faces: the floor and the box's six faces.
  Eigen::Vector3d c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ();
  std::vector<PlaneRect> faces = {{{0, 0, floor_z}, Y, X, 0.3, 0.3},
                                  {c + h.x() * X, Y, Z, h.y(), h.z()},  {c - h.x() * X, Z, Y, h.z(), h.y()},
                                  {c + h.y() * Y, Z, X, h.z(), h.x()},  {c - h.y() * Y, X, Z, h.x(), h.z()},
                                  {c + h.z() * Z, X, Y, h.x(), h.y()},  {c - h.z() * Z, Y, X, h.y(), h.x()}};
  const Eigen::Vector3d cam_o = Eigen::Vector3d::Zero(), laser_o = laser.origin_in_cam();
  const double tol = 1e-7;  // metres: candidates this close to an edge or shadow boundary are ambiguous
  std::map<int, std::vector<double>> expected;
  std::set<int> ambiguous;
  std::map<size_t, int> per_face;
  for (int v = 0; v < cam.height(); ++v) {
    for (size_t f = with_floor ? 0 : 1; f < faces.size(); ++f) {
      const PlaneRect& r = faces[f];
      auto [X0, L] = PlaneLine(laser.SheetPlane(0), r);
      auto P = SolveOnLine(cam, X0, L, v, 0.5);
      if (!P) continue;
      double sa = (*P - r.c).dot(r.a), sb = (*P - r.c).dot(r.b);
      if (std::abs(sa) > r.ha + tol || std::abs(sb) > r.hb + tol) continue;
      if (std::abs(std::abs(sa) - r.ha) < tol || std::abs(std::abs(sb) - r.hb) < tol) {
        ambiguous.insert(v);
        continue;
      }
      double to_cam = r.n().dot(cam_o - *P), to_laser = r.n().dot(laser_o - *P);
      if (to_cam <= 0 || to_laser <= 0) continue;
      bool hidden = SegmentHitsBox(cam_o, *P, lo, hi, -tol), hidden_strict = SegmentHitsBox(cam_o, *P, lo, hi, tol);
      bool shadow = SegmentHitsBox(*P, laser_o, lo, hi, -tol), shadow_strict = SegmentHitsBox(*P, laser_o, lo, hi, tol);
      if (hidden != hidden_strict || shadow != shadow_strict) {
        ambiguous.insert(v);
        continue;
      }
      auto px = cam.Project(*P);
      if (!hidden && !shadow && px && cam.InImage(*px)) {
        expected[v].push_back(px->x());
        ++per_face[f];
      }
    }
  }
  std::map<int, std::vector<double>> got;
  for (const auto& ctr : centers) got[int(std::lround(ctr.v))].push_back(ctr.u);
  int rows = 0;
  for (int v = 0; v < cam.height(); ++v) {
    if (ambiguous.count(v)) continue;
    auto e = expected[v], g = got[v];
    std::sort(e.begin(), e.end());
    std::sort(g.begin(), g.end());
    EXPECT_EQ(e.size(), g.size()) << "row " << v << " " << what;
    if (e.size() != g.size()) continue;
    for (size_t i = 0; i < e.size(); ++i) EXPECT_NEAR(g[i], e[i], 1e-3) << "row " << v << " " << what;
    ++rows;
  }
  EXPECT_GT(rows, cam.height() * 9 / 10) << what;
  return per_face;
}

TEST(StripeTruth, BoxOnAFloorMatchesClosedForm) {
  for (bool distorted : {false, true}) {
    Camera cam = distorted ? DistortedCamera() : test::TestCamera(200, 150, 180);
    std::map<size_t, int> per_face = ExpectBoxMatchesClosedForm(
        cam, test::TestLaser(0.03, 0.11), {-0.012, -0.015, 0.095}, {0.014, 0.011, 0.12}, distorted ? "distorted" : "");
    // The stripe runs over the floor and the box top (face 6, z = lo), with a jump
    // and hidden floor rows between them.
    EXPECT_GT(per_face[0], 10);
    EXPECT_GT(per_face[6], 10);
  }
}

// The stripe on the box top runs 0.15 px inside its edge, beyond the last pixel
// centre on the top; past the edge the floor lies on the same side of the sheet
// as that centre (the laser on the box's side, its floor stripe in the box's
// shadow). No pixel centres bracket the root: it is found by searching the top
// up to the edge, where the line jumps to the floor.
TEST(StripeTruth, StripeBetweenTheLastPixelCentreAndAnEdge) {
  const double fx = 180, top_z = 0.095;
  const double root_x = -0.03 * (1 - top_z / 0.11);           // the sheet on the top
  const double edge_x = root_x + 0.15 * top_z / fx;           // 0.15 px beyond it, before the next centre
  for (bool distorted : {false, true}) {
    Camera cam = distorted ? DistortedCamera() : test::TestCamera(200, 150, fx);
    std::map<size_t, int> per_face = ExpectBoxMatchesClosedForm(cam, test::TestLaser(-0.03, 0.11),
                                                                {-0.04, -0.015, top_z}, {edge_x, 0.011, 0.12},
                                                                distorted ? "distorted" : "");
    EXPECT_GT(per_face[6], 20);  // rows whose centre lies on the top, next to the edge
  }
}

// As above, at a silhouette: a 10 um thin plate with nothing behind it, the
// stripe on its face 0.15 px inside its edge. Beyond the edge the line meets
// nothing (its wall is 0.001 px wide), so only the face searched up to its edge
// holds the root.
TEST(StripeTruth, StripeBetweenTheLastPixelCentreAndASilhouette) {
  const double fx = 180, top_z = 0.095;
  const double root_x = -0.03 * (1 - top_z / 0.11);
  const double edge_x = root_x + 0.15 * top_z / fx;
  for (bool distorted : {false, true}) {
    Camera cam = distorted ? DistortedCamera() : test::TestCamera(200, 150, fx);
    std::map<size_t, int> per_face =
        ExpectBoxMatchesClosedForm(cam, test::TestLaser(-0.03, 0.11), {-0.04, -0.015, top_z},
                                   {edge_x, 0.011, top_z + 1e-5}, distorted ? "distorted" : "", false);
    EXPECT_GT(per_face[6], 20);
  }
}

// A box's wall nearly in line with the camera, seen over `px` between the
// floor (before it) and the box's top (after it), the sheet crossing the wall
// far from both: the sign change between the pixel centres on the floor and
// the top is refined on to the wall.
void ExpectCentresOnAWallSeenOver(double px) {
  const double fx = 180, top_z = 0.095, floor_z = 0.12;
  const double wall_x = px / (fx * (1 / top_z - 1 / floor_z));  // seen over px
  World world;
  world.Add(test::Rectangle({0, 0, floor_z}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.3, 0.3));
  world.Add(test::Box({wall_x, -0.015, top_z}, {0.04, 0.015, floor_z}));
  world.Build();
  const Camera cam = test::TestCamera(200, 150, fx);
  const std::vector<LaserProjector> lasers = {test::TestLaser(-0.03, 0.11)};
  const auto centers = ComputeStripeCenters(*world.embree, cam, lasers, Pose::Identity(), ScanAxis::kRows);
  // The sheet x / -0.03 + z / 0.11 = 1 meets the wall at z = 0.11 (1 + wall_x / 0.03).
  const double z = 0.11 * (1 + wall_x / 0.03);
  int on_wall = 0;
  for (const StripeCenter& c : centers) {
    if (std::abs(c.p_cam.x() - wall_x) < 1e-7 && std::abs(c.p_cam.y()) < 0.015) {
      EXPECT_NEAR(c.p_cam.z(), z, 1e-6) << "row " << c.v << ", seen over " << px << " px";
      ++on_wall;
    }
  }
  // Rows over the box: |y| < 0.015 at z = 0.11, 49 rows at fx 180.
  EXPECT_GE(on_wall, 45) << "seen over " << px << " px";
}

// A bracket still spanning two surfaces once narrower than 1e-4 px is taken
// for a depth discontinuity; taking it so at 0.3 px loses every centre on a
// wall seen over 0.1 px (0 of 49).
TEST(StripeTruth, StripeOnAWallSeenOverATenthOfAPixel) { ExpectCentresOnAWallSeenOver(0.1); }

// Seen over 0.01 px, the wall spans 1.4 um over the final 1e-6 px bracket,
// twice the 1e-3 footprints that ends of a crossing may lie apart: every
// centre on it was rejected as a discontinuity (0 of 49) until ends on one
// plane counted as converged.
TEST(StripeTruth, StripeOnAWallSeenOverAHundredthOfAPixel) {
  ExpectCentresOnAWallSeenOver(0.01);
  ExpectCentresOnAWallSeenOver(0.001);
  // Walls seen over 0.02-0.03 px lost their centres to the same gap check
  // before ends on one plane counted as converged.
  ExpectCentresOnAWallSeenOver(0.02);
  ExpectCentresOnAWallSeenOver(0.03);
}

// The stripe on the wall of a 0.5 mm slot, and the same scene and scanner
// 1 km from the world origin: the same centres. The lit test's shadow ray
// starts off the surface by an offset that scaled with the distance from the
// world origin (1 mm at 1 km), which put its start inside the slot's other
// wall: every centre on the wall was lost (the demo part 1 km away lost the
// centres on its slot walls), while the render frame keeps the geometry exact.
TEST(StripeTruth, SlotWallFarFromTheOriginIsLitAsAtTheOrigin) {
  const double top = 0.127, bottom = 0.131;
  const Eigen::Vector3d far(1000.0, -300.0, 20.0);
  auto centres_at = [&](const Eigen::Vector3d& offset) {
    World world;
    Eigen::Affine3d place = Eigen::Affine3d::Identity();
    place.translation() = offset;
    world.Add(test::Box({-0.03, -0.01, top}, {-0.005, 0.01, bottom}), place);   // its +x face: the lit wall
    world.Add(test::Box({-0.0045, -0.01, top}, {0.03, 0.01, bottom}), place);   // 0.5 mm further: the slot
    world.Build();
    Pose world_from_cam = Pose::Identity();
    world_from_cam.translation() = offset;
    std::vector<LaserProjector> lasers = {test::TestLaser(0.03, 0.11)};
    return ComputeStripeCenters(*world.embree, test::TestCamera(200, 150, 180), lasers, world_from_cam,
                                ScanAxis::kRows);
  };
  const auto near = centres_at(Eigen::Vector3d::Zero()), away = centres_at(far);
  int on_wall = 0;
  for (const auto& c : near) on_wall += std::abs(c.p_world.x() + 0.005) < 1e-9;
  EXPECT_GT(on_wall, 20);  // the stripe runs down the wall, inside the slot
  ASSERT_EQ(away.size(), near.size());
  for (size_t i = 0; i < near.size(); ++i) {
    EXPECT_NEAR(away[i].u, near[i].u, 1e-4) << i;
    EXPECT_NEAR(away[i].v, near[i].v, 1e-4) << i;
    EXPECT_LT((away[i].p_world - far - near[i].p_world).norm(), 1e-7) << i;
  }
}

TEST(StripeTruth, CsvHasTheDocumentedHeader) {
  StripeCenter c;
  c.u = 1.5;
  c.v = 2;
  std::string csv = StripeCentersCsv({c});
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "u,v,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world");
}

}  // namespace
}  // namespace lt

// The planes of plane identification's ranks (pipeline/plane_id_sheets.h):
// one projector's fan keeps one order; facing projectors' sheets swap places
// with depth, and a rank is a plane only where one order fits the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "pipeline/plane_id_sheets.h"
#include "small_camera.h"

namespace lt::test {
namespace {

// The camera: SmallCamera (small_camera.h), 160 x 120, f = 200 px.

// A sheet from a projector at x = baseline (on the camera's x axis) holding
// the y direction and the points x = baseline + slope z: its stripe stands at
// x / z = baseline / z + slope in the image.
struct Sheet {
  double baseline, slope;
  Plane ToPlane() const { return Plane::FromPointNormal({baseline, 0, 0}, {1, 0, -slope}); }
};

// The points a flat surface at depth z(row) shows on every row, each with its
// rank across the row (as plane identification numbers a row meeting all N
// stripes), and each point's true plane.
std::vector<StripePoint> FlatRows(const std::vector<Sheet>& sheets, double (*depth)(int), std::vector<int>* truth) {
  std::vector<StripePoint> points;
  truth->clear();
  for (int v = 0; v < 120; ++v) {
    const double z = depth(v);
    std::vector<std::pair<double, int>> row;
    for (size_t k = 0; k < sheets.size(); ++k) row.push_back({200 * (sheets[k].baseline / z + sheets[k].slope) + 79.5, int(k)});
    std::sort(row.begin(), row.end());
    for (size_t r = 0; r < row.size(); ++r) {
      points.push_back({row[r].first, double(v), 4, 100, int(r)});
      truth->push_back(row[r].second);
    }
  }
  return points;
}

struct Outcome {
  int right = 0, wrong = 0, none = 0;
};
Outcome Score(const std::vector<StripePoint>& points, const std::vector<int>& truth) {
  Outcome o;
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].plane < 0) {
      ++o.none;
    } else {
      ++(points[i].plane == truth[i] ? o.right : o.wrong);
    }
  }
  return o;
}

// Two sheets from a projector 40 mm to the right (spacing 0.08) and two from
// one 30 mm to the left (spacing 0.10): at 100 mm the stripes stand A0 B0 A1
// B1 across the image, at 90 mm B0 A0 B1 A1 (A0 and B0 cross at 94.6 mm, A1
// and B1 at 92.1 mm). A part whose top at 90 mm covers rows 60..119 over a
// bed at 100 mm: each rank stood for the plane the reference depth's order
// gives it (PlanesInImageOrder), so the part's rows had all four stripes on
// the wrong sheet (240 points). Now a rank is a plane only where one of the
// orders the sheets take over depth fits the row (each point on its plane at a
// depth where that order holds): no point on a wrong sheet.
TEST(SheetsOfRanks, FacingProjectorsSwappingAtAStepGetNoWrongSheet) {
  const std::vector<Sheet> sheets = {{0.04, -0.38}, {0.04, -0.30}, {-0.03, 0.36}, {-0.03, 0.46}};
  std::vector<Plane> planes;
  for (const Sheet& s : sheets) planes.push_back(s.ToPlane());
  const Triangulator triangulator(SmallCamera(), planes);
  const SheetsOfRanks sheets_of_ranks(triangulator, SearchAxis::kRows);
  EXPECT_TRUE(sheets_of_ranks.depth_dependent());

  std::vector<int> truth;
  std::vector<StripePoint> points = FlatRows(sheets, [](int v) { return v < 60 ? 0.1 : 0.09; }, &truth);
  const std::vector<int> order = PlanesInImageOrder(planes, SearchAxis::kRows);
  std::vector<StripePoint> by_reference = points;
  for (StripePoint& p : by_reference) p.plane = order[size_t(p.plane)];
  const Outcome before = Score(by_reference, truth);
  EXPECT_EQ(before.wrong, 240);  // the defect: the part's rows, all on wrong sheets

  const int dropped = sheets_of_ranks.Apply(&points);
  const Outcome after = Score(points, truth);
  EXPECT_EQ(after.wrong, 0);
  EXPECT_EQ(after.none, dropped);
  EXPECT_EQ(after.right, 480);  // the spacings differ: one order fits each row
}

// The stripes' positions off by up to 0.5 px (a fixed pseudo-random pattern),
// the part at depths around and between the crossings (85 to 110 mm), the
// second projector's spacing 0.08 to 0.12: no point on a wrong sheet. Near a
// crossing, where two stripes stand closer than 3 px, or where both readings
// fit, points keep no plane.
TEST(SheetsOfRanks, FacingProjectorsWithNoisyStripesGetNoWrongSheet) {
  int right = 0;
  for (double spacing : {0.08, 0.10, 0.12}) {
    const std::vector<Sheet> sheets = {{0.04, -0.38}, {0.04, -0.30}, {-0.03, 0.36}, {-0.03, 0.36 + spacing}};
    std::vector<Plane> planes;
    for (const Sheet& s : sheets) planes.push_back(s.ToPlane());
    const Triangulator triangulator(SmallCamera(), planes);
    const SheetsOfRanks sheets_of_ranks(triangulator, SearchAxis::kRows);
    for (double part : {0.085, 0.09, 0.093, 0.096, 0.105, 0.11}) {
      static double part_depth;
      part_depth = part;
      std::vector<int> truth;
      std::vector<StripePoint> points = FlatRows(sheets, [](int v) { return v < 60 ? 0.1 : part_depth; }, &truth);
      for (size_t i = 0; i < points.size(); ++i) points[i].u += 0.5 * std::sin(12.9898 * double(i) + 78.233);
      // The noise may reorder close stripes: ranks are read again across each row.
      for (size_t i = 0; i < points.size(); i += 4) {
        std::vector<size_t> idx = {i, i + 1, i + 2, i + 3};
        std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return points[a].u < points[b].u; });
        for (int r = 0; r < 4; ++r) points[idx[size_t(r)]].plane = r;
      }
      sheets_of_ranks.Apply(&points);
      const Outcome o = Score(points, truth);
      EXPECT_EQ(o.wrong, 0) << "spacing " << spacing << ", part at " << part;
      right += o.right;
    }
  }
  EXPECT_GT(right, 8640 / 3);  // 18 frames of 480 points
}

// The same with both projectors' sheets 0.08 apart: A0 and B0, A1 and B1
// cross at one depth (94.6 mm). The part's rows read with the bed's order put
// every point at a depth where that order holds, and the bed's rows read with
// the part's order likewise: both orders fit every row, and no point gets a
// plane (none is guessed).
TEST(SheetsOfRanks, FacingProjectorsCrossingAtOneDepthLeaveTheirMirrorUnnumbered) {
  const std::vector<Sheet> sheets = {{0.04, -0.38}, {0.04, -0.30}, {-0.03, 0.36}, {-0.03, 0.44}};
  std::vector<Plane> planes;
  for (const Sheet& s : sheets) planes.push_back(s.ToPlane());
  const Triangulator triangulator(SmallCamera(), planes);
  const SheetsOfRanks sheets_of_ranks(triangulator, SearchAxis::kRows);
  std::vector<int> truth;
  std::vector<StripePoint> points = FlatRows(sheets, [](int v) { return v < 60 ? 0.1 : 0.09; }, &truth);
  const std::vector<int> order = PlanesInImageOrder(planes, SearchAxis::kRows);
  std::vector<StripePoint> by_reference = points;
  for (StripePoint& p : by_reference) p.plane = order[size_t(p.plane)];
  EXPECT_EQ(Score(by_reference, truth).wrong, 240);
  sheets_of_ranks.Apply(&points);
  const Outcome o = Score(points, truth);
  EXPECT_EQ(o.wrong, 0);
  EXPECT_EQ(o.none, 480) << o.right;
}

// The mirror-image rig (A0/B0 and A1/B1 cross at 94.6 mm, A1/B0 at 106 mm)
// with a part at 98 mm over a bed at 102 mm: without a depth range each row
// reads as well as a surface short of 94.6 mm, and none of the 480 points was
// numbered. The scanner's working range 96 to 105 mm holds one order: every
// point right.
TEST(SheetsOfRanks, MirrorImageRigIsNumberedWithinItsDepthRange) {
  const std::vector<Sheet> sheets = {{0.04, -0.38}, {0.04, -0.30}, {-0.03, 0.36}, {-0.03, 0.44}};
  std::vector<Plane> planes;
  for (const Sheet& s : sheets) planes.push_back(s.ToPlane());
  const Triangulator triangulator(SmallCamera(), planes);
  std::vector<int> truth;
  const std::vector<StripePoint> points = FlatRows(sheets, [](int v) { return v < 60 ? 0.102 : 0.098; }, &truth);

  std::vector<StripePoint> unranged = points;
  SheetsOfRanks(triangulator, SearchAxis::kRows).Apply(&unranged);
  EXPECT_EQ(Score(unranged, truth).none, 480);  // before: both readings fit

  std::vector<StripePoint> ranged = points;
  const SheetsOfRanks sheets_of_ranks(triangulator, SearchAxis::kRows, DepthRange{0.096, 0.105});
  EXPECT_TRUE(sheets_of_ranks.depth_dependent());
  EXPECT_EQ(sheets_of_ranks.Apply(&ranged), 0);
  const Outcome o = Score(ranged, truth);
  EXPECT_EQ(o.right, 480);
  EXPECT_EQ(o.wrong, 0);
}

// A point whose depth on the sheet its rank gives lies outside the range
// keeps no plane: the part's rows at 98 mm with the range 100 to 105 mm
// (their other reading, at about 91 mm, lies outside it too), and one
// projector's fan over depths 80 to 139.5 mm with the range 90.1 to 119.9 mm.
TEST(SheetsOfRanks, PointsOutsideTheDepthRangeKeepNoPlane) {
  {
    const std::vector<Sheet> sheets = {{0.04, -0.38}, {0.04, -0.30}, {-0.03, 0.36}, {-0.03, 0.44}};
    std::vector<Plane> planes;
    for (const Sheet& s : sheets) planes.push_back(s.ToPlane());
    const Triangulator triangulator(SmallCamera(), planes);
    std::vector<int> truth;
    std::vector<StripePoint> points = FlatRows(sheets, [](int v) { return v < 60 ? 0.102 : 0.098; }, &truth);
    EXPECT_EQ(SheetsOfRanks(triangulator, SearchAxis::kRows, DepthRange{0.1, 0.105}).Apply(&points), 240);
    int right = 0;
    for (size_t i = 0; i < points.size(); ++i) right += points[i].plane == (points[i].v < 60 ? truth[i] : -1);
    EXPECT_EQ(right, 480);
  }
  std::vector<Sheet> sheets;
  for (int k = 0; k < 5; ++k) sheets.push_back({0.04, -0.5 + 0.05 * k});
  std::vector<Plane> planes;
  for (const Sheet& s : sheets) planes.push_back(s.ToPlane());
  const Triangulator triangulator(SmallCamera(), planes);
  const SheetsOfRanks sheets_of_ranks(triangulator, SearchAxis::kRows, DepthRange{0.0901, 0.1199});
  EXPECT_FALSE(sheets_of_ranks.depth_dependent());
  std::vector<int> truth;
  std::vector<StripePoint> points = FlatRows(sheets, [](int v) { return 0.08 + 0.0005 * v; }, &truth);
  EXPECT_EQ(sheets_of_ranks.Apply(&points), 5 * (20 + 41));  // rows 0..20 and 80..119
  int right = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    right += points[i].plane == (points[i].v > 20 && points[i].v < 80 ? truth[i] : -1);
  }
  EXPECT_EQ(right, int(points.size()));
}

TEST(SheetsOfRanks, DepthRangeIsMillimetresMinColonMax) {
  const DepthRange r = ParseDepthRange("60:120", "--depth-range");
  EXPECT_DOUBLE_EQ(r.near_m, 0.06);
  EXPECT_DOUBLE_EQ(r.far_m, 0.12);
  for (const char* bad : {"60", "60:", ":120", "120:60", "0:120", "-5:120", "60:inf", "a:b", "60:60"}) {
    try {
      ParseDepthRange(bad, "--depth-range");
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--depth-range"), std::string::npos) << e.what();
    }
  }
}

TEST(SheetsOfRanks, OneProjectorsFanKeepsTheImageOrder) {
  std::vector<Sheet> sheets;
  for (int k = 0; k < 5; ++k) sheets.push_back({0.04, -0.5 + 0.05 * k});
  std::vector<Plane> planes;
  for (const Sheet& s : sheets) planes.push_back(s.ToPlane());
  std::swap(planes[0], planes[3]);  // plane numbers need not follow the image order
  std::swap(sheets[0], sheets[3]);
  const Triangulator triangulator(SmallCamera(), planes);
  const SheetsOfRanks sheets_of_ranks(triangulator, SearchAxis::kRows);
  EXPECT_FALSE(sheets_of_ranks.depth_dependent());
  std::vector<int> truth;
  std::vector<StripePoint> points = FlatRows(sheets, [](int v) { return 0.08 + 0.0005 * v; }, &truth);
  EXPECT_EQ(sheets_of_ranks.Apply(&points), 0);
  const Outcome o = Score(points, truth);
  EXPECT_EQ(o.right, int(points.size()));
}

}  // namespace
}  // namespace lt::test

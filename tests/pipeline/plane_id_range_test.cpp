// Plane identification with the scanner's working range (IdentifyPlanes's
// range_fit, SheetsOfRanks::RanksFit): a line of fewer stripes than sheets
// could be several sets of the sheets (N - 1 one spacing apart: either end's);
// the range decides when it leaves one numbering.
#include <gtest/gtest.h>

#include <string>

#include "pipeline/plane_id_sheets.h"
#include "pipeline/plane_identification.h"
#include "small_camera.h"

namespace lt::test {
namespace {

// SmallCamera (small_camera.h: 160 x 120, f = 200 px) and N sheets of one projector 40 mm
// to the right, each holding the y direction: sheet k's stripe stands at
// u = 79.5 + 200 (0.04 / z + slope_k), slopes 0.1 apart (20 px), so a stripe
// read as its neighbour's sheet lies 20 mm nearer or 33 mm farther at 100 mm.
double Slope(int k) { return -0.6 + 0.1 * k; }

// A surface at 95 to 107 mm (z = 0.095 + 0.0001 v) lit by sheets 0..N-1 but
// for `missing` (on rows v < 60 only `missing_upper`, on the others
// `missing`), searched along rows; each point's true sheet.
std::vector<StripePoint> Surface(int n, int missing, int missing_upper, std::vector<int>* truth) {
  std::vector<StripePoint> points;
  truth->clear();
  for (int v = 0; v < 120; ++v) {
    const double z = 0.095 + 0.0001 * v;
    for (int k = 0; k < n; ++k) {
      if (k == (v < 60 ? missing_upper : missing)) continue;
      points.push_back({79.5 + 200 * (0.04 / z + Slope(k)), double(v), 4, 100, -1});
      truth->push_back(k);
    }
  }
  return points;
}

struct Numbered {
  int right = 0, wrong = 0, none = 0;
  std::string error;
};
Numbered Identify(const std::vector<StripePoint>& points, const std::vector<int>& truth, const Triangulator& triangulator,
                  std::optional<DepthRange> range) {
  const SheetsOfRanks sheets(triangulator, SearchAxis::kRows, range);
  const RankFit fit = range ? RankFit([&](const std::vector<StripePoint>& line) { return sheets.RanksFit(line); })
                            : RankFit();
  PlaneIdentification id = IdentifyPlanes(points, {0, 0, 160, 120}, int(triangulator.planes().size()), PlaneIdOptions{}, fit);
  Numbered out;
  out.error = id.error;
  if (id.ok) sheets.Apply(&id.points);
  for (size_t i = 0; i < id.points.size(); ++i) {
    const int plane = id.ok ? id.points[i].plane : -1;
    ++(plane < 0 ? out.none : plane == truth[i] ? out.right : out.wrong);
  }
  return out;
}

// One sheet (an end's or an inner one) missing on every row, N = 3..5: no
// line meets all N, and a line of N - 1 stripes could be either end's sheets
// (or, N = 3 with the middle one missing, 2 stripes 2 spacings apart, sheets
// 0 and 2 or, 2 spacings read as one, 0 and 1 or 1 and 2). Before, the
// frame was refused whatever the range (no point numbered). With
// 90:110 mm only the true numbering puts every stripe within the range:
// every point on its sheet. With 50:200 mm several numberings do, and with no
// range nothing decides: no point numbered, and the reason says so.
TEST(PlaneIdRange, ASheetMissingOnEveryLineIsNumberedWhenTheRangeDecides) {
  for (int n = 3; n <= 5; ++n) {
    std::vector<Plane> planes;
    for (int k = 0; k < n; ++k) planes.push_back(Plane::FromPointNormal({0.04, 0, 0}, {1, 0, -Slope(k)}));
    const Triangulator triangulator(SmallCamera(), planes);
    for (int missing = 0; missing < n; ++missing) {
      SCOPED_TRACE(std::to_string(n) + " sheets, sheet " + std::to_string(missing) + " missing");
      std::vector<int> truth;
      const std::vector<StripePoint> points = Surface(n, missing, missing, &truth);
      const Numbered decided = Identify(points, truth, triangulator, DepthRange{0.09, 0.11});
      EXPECT_EQ(decided.right, int(points.size())) << decided.error;
      EXPECT_EQ(decided.wrong, 0);
      const Numbered wide = Identify(points, truth, triangulator, DepthRange{0.05, 0.2});
      const Numbered unranged = Identify(points, truth, triangulator, std::nullopt);
      if (n > 3 && missing > 0 && missing < n - 1) {
        // Spacings of 1 and 2 adding up to N - 1 span the N sheets: numbered
        // without a range, as before.
        EXPECT_EQ(wide.right, int(points.size())) << wide.error;
        EXPECT_EQ(unranged.right, int(points.size())) << unranged.error;
        continue;
      }
      EXPECT_EQ(wide.none, int(points.size()));
      EXPECT_NE(wide.error.find("more than one numbering puts them within the depth range"), std::string::npos)
          << wide.error;
      EXPECT_EQ(unranged.none, int(points.size()));
      EXPECT_NE(unranged.error.find("show fewer, which could be more than one set of the sheets"), std::string::npos)
          << unranged.error;
    }
  }
}

// Sheet 0 missing on the upper rows and sheet N - 1 on the lower ones: every
// line shows N - 1 stripes one spacing apart, the first end's on some lines
// and the last end's on the others (refused before). The range numbers both.
TEST(PlaneIdRange, EitherEndsSheetsOnDifferentLinesAreNumberedByTheRange) {
  for (int n = 3; n <= 5; ++n) {
    SCOPED_TRACE(std::to_string(n) + " sheets");
    std::vector<Plane> planes;
    for (int k = 0; k < n; ++k) planes.push_back(Plane::FromPointNormal({0.04, 0, 0}, {1, 0, -Slope(k)}));
    const Triangulator triangulator(SmallCamera(), planes);
    std::vector<int> truth;
    const std::vector<StripePoint> points = Surface(n, n - 1, 0, &truth);
    const Numbered decided = Identify(points, truth, triangulator, DepthRange{0.09, 0.11});
    EXPECT_EQ(decided.right, int(points.size())) << decided.error;
    EXPECT_EQ(Identify(points, truth, triangulator, DepthRange{0.05, 0.2}).none, int(points.size()));
  }
}

}  // namespace
}  // namespace lt::test

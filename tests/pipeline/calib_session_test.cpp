// Session helpers of pipeline/calib_session.h that need no rendered run: the
// multi-line grouping of stripe pieces on the flat board, and the board file.
// (The whole chain on a rendered session is tests/cli/calibrate_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "core/error.h"
#include "pipeline/calib_session.h"

namespace lt {
namespace {

// Three stripes across a 640-column image (searched along columns: u is the
// column, v the subpixel row), nearly parallel with perspective, each broken
// every 30 columns as on black squares, plus one short stray piece.
std::vector<StripePoint> ThreeBrokenStripes(int* stray_first) {
  std::vector<StripePoint> pts;
  const double a[3] = {100, 170, 240}, b[3] = {0.30, 0.32, 0.34};
  for (int u = 40; u < 600; ++u) {
    if ((u / 30) % 2 == 1) continue;  // the stripe is too dim on black squares
    for (int k = 0; k < 3; ++k) {
      StripePoint p;
      p.u = u;
      p.v = a[k] + b[k] * u + 0.2 * std::sin(0.7 * u + k);  // 0.2 px of wobble
      p.plane = 7;
      pts.push_back(p);
    }
  }
  *stray_first = int(pts.size());
  for (int u = 300; u < 308; ++u) pts.push_back(StripePoint{double(u), 420.0 + 0.1 * u, 2, 1, 7});
  return pts;
}

TEST(CalibSessionGrouping, JoinsTheBrokenPiecesOfEachStripeInImageOrder) {
  int stray_first = 0;
  const std::vector<StripePoint> pts = ThreeBrokenStripes(&stray_first);
  PlaneIdOptions o;
  o.axis = SearchAxis::kCols;
  const PlaneIdentification id = IdentifyPlanes(pts, PixelRect{0, 0, 640, 512}, 3, o);
  ASSERT_GT(id.segments.size(), 20u);  // the stripes come in pieces
  std::vector<StripePoint> grouped = id.points;
  std::string error;
  ASSERT_TRUE(GroupStripesOnFlatTarget(&grouped, id.segments, 3, SearchAxis::kCols, 3.0, &error)) << error;
  for (int i = 0; i < stray_first; ++i) EXPECT_EQ(grouped[size_t(i)].plane, i % 3) << i;  // top to bottom
  for (size_t i = size_t(stray_first); i < grouped.size(); ++i) EXPECT_EQ(grouped[i].plane, -1) << i;
}

TEST(CalibSessionGrouping, RefusesAnotherNumberOfLines) {
  int stray_first = 0;
  std::vector<StripePoint> pts = ThreeBrokenStripes(&stray_first);
  pts.resize(size_t(stray_first));
  std::vector<StripePoint> two;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (i % 3 != 1) two.push_back(pts[i]);  // the middle sheet missed the board
  }
  PlaneIdOptions o;
  o.axis = SearchAxis::kCols;
  const PlaneIdentification id = IdentifyPlanes(two, PixelRect{0, 0, 640, 512}, 3, o);
  std::vector<StripePoint> grouped = id.points;
  std::string error;
  EXPECT_FALSE(GroupStripesOnFlatTarget(&grouped, id.segments, 3, SearchAxis::kCols, 3.0, &error));
  EXPECT_EQ(error, "found 2 stripe line(s) on the board, expected 3");
}

TEST(CalibSessionBoard, BoardFileIsReadStrictly) {
  const auto dir = std::filesystem::temp_directory_path() / ("lt_calib_board_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& text) {
    std::ofstream(dir / "checkerboard.json") << text;
    return dir / "checkerboard.json";
  };
  const CheckerboardSpec b = ReadCheckerboardFile(write(R"({"rows": 6, "cols": 9, "square_mm": 2.5})"));
  EXPECT_EQ(b.rows, 6);
  EXPECT_EQ(b.cols, 9);
  EXPECT_DOUBLE_EQ(b.square_m, 2.5e-3);
  EXPECT_EQ(b.margin_squares, 1);
  for (const char* bad : {R"({"rows": 6, "cols": 8, "square_mm": 3})", R"({"rows": 6, "cols": 9, "square_mm": 0})",
                          R"({"rows": 6, "cols": 9, "square_mm": 3, "colour": 1})", R"({"rows": 6, "cols": 9})"}) {
    try {
      ReadCheckerboardFile(write(bad));
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("checkerboard.json"), std::string::npos) << e.what();
    }
  }
  // A run folder without a scene names what is missing.
  try {
    FindSessionBoardFile(dir);
    ADD_FAILURE() << "found a board without a scene";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lt

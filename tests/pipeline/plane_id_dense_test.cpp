// Plane identification of many sheets close together (a diffractive element's
// 5 to 11 lines): pieces that lines meeting only some of the sheets number,
// and pieces of two sheets joined at a depth step.
#include <gtest/gtest.h>

#include "pipeline/plane_identification.h"

namespace lt::test {
namespace {

// Points of a vertical line at column u over rows [a, b), and their sheet.
void AddLine(std::vector<StripePoint>* pts, std::vector<int>* truth, int sheet, double u, int a, int b) {
  for (int v = a; v < b; ++v) pts->push_back({u, double(v), 4, 100, -1}), truth->push_back(sheet);
}

// Every point plane identification numbered carries its true sheet, with the
// frame read by stripe order; returns how many it numbered.
int ExpectNumberedRight(const std::vector<StripePoint>& pts, const std::vector<int>& truth,
                        const PlaneIdentification& id) {
  EXPECT_TRUE(id.ok) << id.error;
  EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder) << id.order_error;
  if (!id.ok) return 0;
  int numbered = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (id.points[i].plane < 0) continue;
    ++numbered;
    EXPECT_EQ(id.points[i].plane, truth[i]) << pts[i].u << "," << pts[i].v;
  }
  return numbered;
}

// A depth step at row 60 moves every stripe by 0.8 spacing towards the first
// sheet, so that sheet 1's stripe above it runs on (2 px across) into sheet
// 2's below it: one segment. The other stripes break at the step; below it no
// line meets or spans all 4 sheets (sheet 0's stripe is seen only from row 90
// on, where the joined segment has ended). Before, the joined segment kept
// sheet 1 below the step (30 points on the wrong sheet), and sheet 1's piece
// there, standing just before it, was numbered 0 by its position (57 more),
// although sheet 0's stripe stands before it from row 90 on.
TEST(PlaneIdDense, PiecesBesideAJoinedPieceLeaveItNoRoom) {
  for (SearchAxis axis : {SearchAxis::kRows, SearchAxis::kCols}) {
    const double spacing = 10, shift = -8;
    std::vector<StripePoint> pts;
    std::vector<int> truth;
    for (int k = 0; k < 4; ++k) {
      if (k == 1) continue;
      AddLine(&pts, &truth, k, 20 + spacing * k, 0, 60);
    }
    AddLine(&pts, &truth, 1, 20 + spacing, 0, 60);  // sheet 1 above the step,
    AddLine(&pts, &truth, 2, 20 + 2 * spacing + shift, 60, 90);  // joined to sheet 2 below it
    AddLine(&pts, &truth, 1, 20 + spacing + shift, 63, 120);
    AddLine(&pts, &truth, 3, 20 + 3 * spacing + shift, 63, 120);
    AddLine(&pts, &truth, 0, 20 + shift, 90, 120);
    PixelRect region{0, 0, 100, 120};
    if (axis == SearchAxis::kCols) {
      for (auto& p : pts) std::swap(p.u, p.v);
      region = {0, 0, 120, 100};
    }
    PlaneIdOptions o;
    o.axis = axis;
    const int numbered = ExpectNumberedRight(pts, truth, IdentifyPlanes(pts, region, 4, o));
    EXPECT_GE(numbered, 4 * 60);  // every stripe above the step
  }
}

// The same step with every sheet's stripe below it joined to the one before
// it above it (a step moving the stripes by 0.8 spacing), and below it only 4
// points of sheet 0 (fewer than --min-segment-points: noise to the
// numbering). No line below the step meets or spans the 4 sheets, so the lines
// above numbered each joined segment whole: 180 points on the wrong sheet
// (multicom on the 9-sheet render at 160x128 after its split of saturated
// stripes: 45). Those 4 points leave the joined pieces no room for their
// numbers below the step; they are cut there.
TEST(PlaneIdDense, AFewPointsBeforeTheFirstStripeLeaveItNoRoom) {
  const double spacing = 10, shift = -8;
  std::vector<StripePoint> pts;
  std::vector<int> truth;
  for (int k = 0; k < 4; ++k) AddLine(&pts, &truth, k, 20 + spacing * k, 0, 60);
  for (int k = 1; k < 4; ++k) AddLine(&pts, &truth, k, 20 + spacing * k + shift, 60, 120);
  AddLine(&pts, &truth, 0, 20 + shift, 60, 64);
  const int numbered = ExpectNumberedRight(pts, truth, IdentifyPlanes(pts, {0, 0, 100, 120}, 4, PlaneIdOptions{}));
  EXPECT_GE(numbered, 4 * 60);
}

// A step that moves every stripe by about a spacing, where one sheet's stripe
// runs on across it into the next sheet's for just two lines before the step
// (the other stripes break at it). Lines meeting all 4 sheets give the joined
// segment its own rank on those two lines and the next rank on the 60 after
// the step; two lines did not cut it (the minimum was 3), so its two points
// before the step took the next sheet (multicom on the 9-sheet render at
// 160x128, 16 spp: 3 points). They are cut off now.
TEST(PlaneIdDense, TwoLinesAtAJoinedSegmentsEndAreCutOff) {
  const double spacing = 10;
  std::vector<StripePoint> pts;
  std::vector<int> truth;
  for (int k = 0; k < 4; ++k) {
    if (k == 2) {
      AddLine(&pts, &truth, k, 20 + spacing * k, 0, 56);
      AddLine(&pts, &truth, k, 20 + spacing * k, 58, 60);  // joined to sheet 3 below the step
    } else {
      AddLine(&pts, &truth, k, 20 + spacing * k, 0, 60);
    }
    if (k == 3) {
      AddLine(&pts, &truth, k, 20 + spacing * k - 8.5, 60, 61);
      AddLine(&pts, &truth, k, 20 + spacing * k - 7, 61, 120);
    } else {
      AddLine(&pts, &truth, k, 20 + spacing * k - 7, 60, 120);
    }
  }
  const int numbered = ExpectNumberedRight(pts, truth, IdentifyPlanes(pts, {0, 0, 100, 120}, 4, PlaneIdOptions{}));
  EXPECT_GE(numbered, 4 * 116);
}

}  // namespace
}  // namespace lt::test

// Multi-line plane identification: segment classification, numbering by the
// stripes' order and by the edge chains, and refusal when neither decides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "pipeline/plane_identification.h"
#include "stripe_test_util.h"

namespace lt::test {
namespace {

// Points of a vertical line at column u over rows [a, b).
void AddLine(std::vector<StripePoint>* pts, double u, int a, int b, double slope = 0) {
  for (int v = a; v < b; ++v) pts->push_back({u + slope * v, double(v), 4, 100, -1});
}

TEST(PlaneIdentification, ClassifiesSegments) {
  std::vector<StripePoint> pts;
  AddLine(&pts, 20, 0, 100);   // LREC
  AddLine(&pts, 50, 2, 40);    // LEC (within the 5-pixel margin of the top)
  AddLine(&pts, 50.5, 50, 70); // F
  AddLine(&pts, 51, 80, 99);   // REC
  AddLine(&pts, 80, 30, 32);   // 2 points: noise
  PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 120, 100}, 2, PlaneIdOptions{});
  ASSERT_EQ(id.segments.size(), 5u);
  std::vector<std::string> types;
  for (const auto& s : id.segments) types.push_back(SegmentTypeName(s.type));
  // Segments are numbered in order of their first point (row, then column).
  EXPECT_EQ(types, (std::vector<std::string>{"LREC", "LEC", "F", "F", "REC"}));
  EXPECT_TRUE(id.segments[2].ignored);  // the noise, first seen at row 30
  EXPECT_FALSE(id.segments[3].ignored);
  ASSERT_TRUE(id.ok) << id.error;
  EXPECT_EQ(id.groups_found, 2);
  for (const auto& p : id.points) {
    const int expected = p.u < 30 ? 0 : p.u < 60 ? 1 : -1;
    EXPECT_EQ(p.plane, expected) << p.u << "," << p.v;
  }
}

TEST(PlaneIdentification, TiltedStripesStayConnected) {
  // 60 degrees from vertical: 1.73 px per row, linked with the default 2 px.
  std::vector<StripePoint> pts;
  AddLine(&pts, 10, 0, 60, std::tan(60 * M_PI / 180));
  PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 200, 60}, 1, PlaneIdOptions{});
  ASSERT_TRUE(id.ok) << id.error;
  EXPECT_EQ(id.segments.size(), 1u);
  PlaneIdOptions strict;
  strict.link_distance = 1;  // 8-connectivity breaks it into pieces
  EXPECT_GT(IdentifyPlanes(pts, {0, 0, 200, 60}, 1, strict).segments.size(), 1u);
}

TEST(PlaneIdentification, ReportsInsteadOfGuessing) {
  std::vector<StripePoint> pts;
  AddLine(&pts, 20, 0, 100);
  AddLine(&pts, 60, 0, 100);
  PlaneIdentification three = IdentifyPlanes(pts, {0, 0, 120, 100}, 3, PlaneIdOptions{});
  EXPECT_FALSE(three.ok);
  EXPECT_NE(three.error.find("found 2"), std::string::npos) << three.error;
  EXPECT_NE(three.error.find("expected 3"), std::string::npos) << three.error;
  EXPECT_NE(three.error.find("no search line meets all 3 stripes"), std::string::npos) << three.error;
  EXPECT_EQ(three.unidentified_segments, 0);
  for (const auto& p : three.points) EXPECT_EQ(p.plane, -1);
  // A third stripe beside two sheets over rows 30..59: the stripes' order
  // numbers the two lines (every other row shows exactly two stripes) and
  // leaves the extra segment, which no row places, without a plane (the edge
  // chains could not join it either).
  AddLine(&pts, 100, 30, 60);
  PlaneIdentification left_over = IdentifyPlanes(pts, {0, 0, 120, 100}, 2, PlaneIdOptions{});
  ASSERT_TRUE(left_over.ok) << left_over.error;
  EXPECT_EQ(left_over.method, PlaneIdMethod::kStripeOrder);
  EXPECT_EQ(left_over.unidentified_segments, 1);
  for (const auto& p : left_over.points) EXPECT_EQ(p.plane, p.u < 40 ? 0 : p.u < 80 ? 1 : -1) << p.u << "," << p.v;
  EXPECT_THROW(IdentifyPlanes(pts, {0, 0, 120, 100}, 0, PlaneIdOptions{}), InputError);
  PlaneIdOptions bad;
  bad.link_distance = 0;
  EXPECT_THROW(IdentifyPlanes(pts, {0, 0, 120, 100}, 2, bad), InputError);
}

// Stripes that do not reach the start edge, where the edge chains fail: the
// stripes' order numbers them. Four sheets; the first starts 10 rows down (past the edge
// margin), the fourth ends at row 50, and the second is cut at rows 50..59, so
// its lower piece is never on a row with all four stripes: it is numbered by
// lying between the first and third stripes with one rank missing between them.
TEST(PlaneIdentification, StripeOrderWhenStripesMissTheStartEdge) {
  std::vector<StripePoint> pts;
  AddLine(&pts, 20, 10, 100);
  AddLine(&pts, 40, 0, 50);
  AddLine(&pts, 40, 60, 100);
  AddLine(&pts, 60, 0, 100);
  AddLine(&pts, 80, 0, 50);
  PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 120, 100}, 4, PlaneIdOptions{});
  ASSERT_TRUE(id.ok) << id.error;
  EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder);
  EXPECT_EQ(id.groups_found, 3);  // the edge chains alone would have failed
  EXPECT_EQ(id.unidentified_segments, 0);
  for (const auto& p : id.points) EXPECT_EQ(p.plane, int(p.u) / 20 - 1) << p.u << "," << p.v;
  // The same with the fourth stripe gone where the second is cut: the lower
  // piece could be the second or the third sheet's, and is left without a plane.
  pts.clear();
  AddLine(&pts, 20, 10, 100);
  AddLine(&pts, 40, 0, 50);
  AddLine(&pts, 40, 60, 100);
  AddLine(&pts, 60, 0, 50);
  PlaneIdentification three = IdentifyPlanes(pts, {0, 0, 120, 100}, 3, PlaneIdOptions{});
  ASSERT_TRUE(three.ok) << three.error;
  EXPECT_EQ(three.unidentified_segments, 1);
  for (const auto& p : three.points) EXPECT_EQ(p.plane, p.u == 40 && p.v >= 60 ? -1 : int(p.u) / 20 - 1);
}

// At a depth step a sheet's stripe jumps across: the piece on the lower surface
// ends on the rows where the piece on the upper one begins, so those rows meet
// the sheet twice (one row where the step runs along the rows, several where it
// runs obliquely). Both pieces are that sheet's; before, the equal numbers on
// one row failed the order, and the edge chains could not join the overlapping
// pieces, so the whole frame went without planes (a rendered 3-sheet frame at a
// part's edge).
TEST(PlaneIdentification, SheetMeetingALineTwiceAtADepthStep) {
  for (int overlap : {1, 6}) {
    std::vector<StripePoint> pts;
    AddLine(&pts, 20, 0, 100);
    AddLine(&pts, 50, 0, 40 + overlap);  // the lower surface's piece, up to the step
    AddLine(&pts, 58, 40, 100);          // the upper surface's piece, from the step
    AddLine(&pts, 90, 0, 100);
    PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 120, 100}, 3, PlaneIdOptions{});
    ASSERT_TRUE(id.ok) << "overlap " << overlap << ": " << id.error;
    EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder) << id.order_error;
    EXPECT_EQ(id.unidentified_segments, 0);
    for (const auto& p : id.points) EXPECT_EQ(p.plane, p.u < 30 ? 0 : p.u < 70 ? 1 : 2) << p.u << "," << p.v;
  }
  // A piece beside a stripe over rows that stripe covers entirely is no step.
  // Where the first stripe is missing, its rows show three stripes, but two of
  // them 3 px apart where the sheets stand 30 to 40 px apart: they do not vote,
  // and the piece keeps no plane (numbered like the stripe beside it, the order
  // would contradict itself).
  std::vector<StripePoint> pts;
  AddLine(&pts, 20, 0, 20);
  AddLine(&pts, 20, 31, 100);
  AddLine(&pts, 50, 0, 100);
  AddLine(&pts, 53, 20, 31);  // beside the second stripe where the first is missing
  AddLine(&pts, 90, 0, 100);
  PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 120, 100}, 3, PlaneIdOptions{});
  ASSERT_TRUE(id.ok) << id.error;
  EXPECT_EQ(id.unidentified_segments, 1);
  for (const auto& p : id.points) {
    if (p.u == 53) {
      EXPECT_EQ(p.plane, -1) << p.u << "," << p.v;
    } else {
      EXPECT_EQ(p.plane, p.u < 30 ? 0 : p.u < 70 ? 1 : 2) << p.u << "," << p.v;
    }
  }
}

// Where the first sheet's stripe is missing (too narrow, dark), a depth step
// that shows the second sheet twice gives lines with exactly two stripes, 4 px
// apart where the sheets stand 50 px apart. Before, those lines numbered the
// step's second piece as the first sheet, and the frame's points there were
// triangulated on the wrong plane; now such lines do not vote and the piece
// keeps no plane.
TEST(PlaneIdentification, AStepBesideAMissingStripeIsNotANewSheet) {
  std::vector<StripePoint> pts;
  AddLine(&pts, 20, 0, 40);
  AddLine(&pts, 20, 61, 100);
  AddLine(&pts, 70, 0, 100);
  AddLine(&pts, 66, 40, 61);  // the second sheet on a slot's floor, where the first is missing
  PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 120, 100}, 2, PlaneIdOptions{});
  ASSERT_TRUE(id.ok) << id.error;
  EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder) << id.order_error;
  EXPECT_EQ(id.unidentified_segments, 1);
  for (const auto& p : id.points) EXPECT_EQ(p.plane, p.u == 66 ? -1 : p.u < 40 ? 0 : 1) << p.u << "," << p.v;
}

// No row meets all three stripes (the third starts where the first ends), so
// the order cannot decide; the edge chains, which need every sheet to reach the
// top, cannot either until the third does: then they number the frame.
TEST(PlaneIdentification, EdgeChainsWhenNoLineMeetsAllStripes) {
  std::vector<StripePoint> pts;
  AddLine(&pts, 20, 0, 50);
  AddLine(&pts, 50, 0, 100);
  AddLine(&pts, 80, 50, 100);
  PlaneIdentification none = IdentifyPlanes(pts, {0, 0, 120, 100}, 3, PlaneIdOptions{});
  EXPECT_FALSE(none.ok);
  EXPECT_NE(none.error.find("no search line meets all 3 stripes"), std::string::npos) << none.error;
  EXPECT_NE(none.error.find("found 2 stripe group(s)"), std::string::npos) << none.error;
  for (const auto& p : none.points) EXPECT_EQ(p.plane, -1);
  // The third sheet's top in rows 0..3 and the second starting at row 4 (both
  // within the 5-row edge margin): still no row with all three.
  pts.clear();
  AddLine(&pts, 20, 0, 50);
  AddLine(&pts, 50, 4, 100);
  AddLine(&pts, 80, 0, 4);
  AddLine(&pts, 80.5, 50, 100);
  PlaneIdOptions o;
  o.min_segment_points = 4;
  PlaneIdentification chains = IdentifyPlanes(pts, {0, 0, 120, 100}, 3, o);
  ASSERT_TRUE(chains.ok) << chains.error;
  EXPECT_EQ(chains.method, PlaneIdMethod::kEdgeChains);
  EXPECT_NE(chains.order_error.find("no search line meets all 3"), std::string::npos) << chains.order_error;
  for (const auto& p : chains.points) EXPECT_EQ(p.plane, p.u < 30 ? 0 : p.u < 60 ? 1 : 2) << p.u << "," << p.v;
}

TEST(PlaneIdentification, ColumnSearchNumbersTopToBottom) {
  std::vector<StripePoint> pts;
  for (int u = 0; u < 80; ++u) {
    pts.push_back({double(u), 40.0 + 0.1 * u, 4, 100, -1});
    pts.push_back({double(u), 10.0, 4, 100, -1});
  }
  PlaneIdOptions o;
  o.axis = SearchAxis::kCols;
  PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 80, 60}, 2, o);
  ASSERT_TRUE(id.ok) << id.error;
  for (const auto& p : id.points) EXPECT_EQ(p.plane, p.v < 20 ? 0 : 1);
}

// A 5-sheet frame: stripes at different tilts, one curved, with gaps that
// break them into LEC, F and REC segments (occlusions). Extraction then
// identification must give every point the plane of the stripe it lies on.
SyntheticFrame FiveSheetFrame() {
  SyntheticFrame f;
  f.width = 420;
  f.height = 240;
  f.noise_sigma = 2;
  f.background = 4;
  f.stripes.push_back(LineStripe(60, 120, -8, 2, 180));
  f.stripes.push_back(LineStripe(135, 120, -3, 2, 200));
  SyntheticStripe arc;
  arc.shape = SyntheticStripe::Shape::kArc;
  arc.cu = -400, arc.cv = 120, arc.radius = 610, arc.sigma = 2, arc.amplitude = 190;
  f.stripes.push_back(arc);
  f.stripes.push_back(LineStripe(280, 120, 4, 2, 170));
  f.stripes.push_back(LineStripe(355, 120, 9, 2, 200));
  f.stripes[0].visible_rows = {{0, 90}, {110, 240}};
  f.stripes[2].visible_rows = {{0, 60}, {80, 150}, {175, 240}};
  f.stripes[3].visible_rows = {{0, 200}, {215, 240}};
  f.stripes[4].visible_rows = {{0, 40}, {52, 130}, {140, 240}};
  return f;
}

// The frame's stripe points by `m` (threshold 60 DN, steger's width 4.7 px),
// identified as 5 planes.
struct IdentifiedFrame {
  std::vector<StripePoint> points;
  PlaneIdentification id;
};
IdentifiedFrame ExtractAndIdentify(const SyntheticFrame& f, ExtractionMethod m) {
  ExtractionOptions o;
  o.method = m;
  o.threshold = 60;
  o.expected_width = 4.7;
  IdentifiedFrame r;
  r.points = ExtractFrom<uint8_t>(f, o);
  PlaneIdOptions po;
  po.edge_margin = std::max(po.edge_margin, o.EdgeLinesWithoutPoints() + 2);
  r.id = IdentifyPlanes(r.points, {0, 0, f.width, f.height}, 5, po);
  return r;
}

// The stripe nearest to a point along its row, and how near.
int NearestStripe(const SyntheticFrame& f, const StripePoint& p, double* distance) {
  int truth = -1;
  *distance = 1e9;
  for (int k = 0; k < int(f.stripes.size()); ++k) {
    const double d = std::abs(p.u - f.stripes[size_t(k)].CentreU(p.v));
    if (d < *distance) *distance = d, truth = k;
  }
  return truth;
}

TEST(PlaneIdentification, FiveSheetFrameEverySegmentOnItsPlane) {
  SyntheticFrame f = FiveSheetFrame();
  for (auto m : {ExtractionMethod::kMultiCom, ExtractionMethod::kSteger}) {
    SCOPED_TRACE(MethodName(m));
    const IdentifiedFrame r = ExtractAndIdentify(f, m);
    ASSERT_GT(r.points.size(), 900u);
    const PlaneIdentification& id = r.id;
    ASSERT_TRUE(id.ok) << id.error;
    int floating = 0, real_segments = 0;
    for (const auto& s : id.segments) {
      if (s.ignored) continue;
      ++real_segments;
      floating += s.type == SegmentType::kFloating;
      for (int i : s.points) {
        const StripePoint& p = id.points[i];
        double distance = 0;
        const int truth = NearestStripe(f, p, &distance);
        ASSERT_LT(distance, 1.0);
        EXPECT_EQ(s.plane, truth) << "point " << p.u << "," << p.v;
      }
    }
    EXPECT_EQ(real_segments, 5 + 1 + 2 + 1 + 2);  // each gap adds a segment
    EXPECT_EQ(floating, 2);                       // the middle pieces of stripes 2 and 4
  }
}

// The five-sheet frame with the second stripe starting 40 rows down (the part
// hides its top): the edge chains could not number it; the stripes' order does.
TEST(PlaneIdentification, FiveSheetFrameWithAStripeBelowTheEdge) {
  SyntheticFrame f = FiveSheetFrame();
  f.stripes[1].visible_rows = {{40, 240}};
  for (auto m : {ExtractionMethod::kMultiCom, ExtractionMethod::kSteger}) {
    SCOPED_TRACE(MethodName(m));
    const IdentifiedFrame r = ExtractAndIdentify(f, m);
    ASSERT_TRUE(r.id.ok) << r.id.error;
    EXPECT_EQ(r.id.method, PlaneIdMethod::kStripeOrder);
    EXPECT_LT(r.id.groups_found, 5);  // the edge chains alone would have failed
    int identified = 0;
    for (const auto& p : r.id.points) {
      if (p.plane < 0) continue;
      ++identified;
      double distance = 0;
      EXPECT_EQ(p.plane, NearestStripe(f, p, &distance)) << "point " << p.u << "," << p.v;
    }
    EXPECT_GT(identified, int(0.95 * r.points.size()));
  }
}

// A speckle blob between the first two stripes on rows where the third sheet's
// stripe is hidden: those rows meet four segments, and before they voted the
// blob sheet 1 and the second stripe sheet 2 (its other rows say 1), so the
// order contradicted itself and, the edge chains failing too, the whole frame
// went without planes. A line that gives a segment another rank than its
// other lines' majority does not vote: the blob keeps no plane, the rest is
// numbered.
TEST(PlaneIdentification, ALineShowingABlobWhereAStripeIsHiddenDoesNotVote) {
  std::vector<StripePoint> pts;
  AddLine(&pts, 20, 0, 120);
  AddLine(&pts, 50, 0, 120);
  AddLine(&pts, 80, 0, 40);
  AddLine(&pts, 80, 61, 120);  // hidden on rows 40..60
  AddLine(&pts, 110, 0, 120);
  AddLine(&pts, 35, 45, 56);  // the blob
  PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 160, 120}, 4, PlaneIdOptions{});
  ASSERT_TRUE(id.ok) << id.error;
  EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder) << id.order_error;
  EXPECT_EQ(id.unidentified_segments, 1);
  for (const auto& p : id.points) EXPECT_EQ(p.plane, p.u == 35 ? -1 : int(p.u) / 30) << p.u << "," << p.v;
}

// N sheets (3 to 6) crossing an oblique depth step that moves each stripe 1.5
// or 2.5 spacings across, the first sheet reaching the step first or last.
// When the first reaches it first, rows between the first and the last sheet's
// step show a sheet past the step beyond neighbours that have not reached it
// (one projector's sheets keep their order on a height field, not beside thin
// walls and ribs). Every piece is numbered by the rows that show all N sheets
// in order; before, the reversed pieces on the step's rows failed the order,
// the edge chains could not join the pieces, and the frame went without planes.
TEST(PlaneIdentification, StripesPassingANeighbourAtAStepKeepTheirSheets) {
  for (int n = 3; n <= 6; ++n) {
    const double spacing = 150.0 / (n + 1);
    for (double jump : {1.5, 2.5}) {
      for (bool first_sheet_first : {true, false}) {
        SCOPED_TRACE(std::to_string(n) + " sheets, jump " + std::to_string(jump) + (first_sheet_first ? ", first" : ", last"));
        std::vector<StripePoint> pts;
        std::vector<int> truth;
        for (int k = 0; k < n; ++k) {
          const int step_row = 50 + 4 * (first_sheet_first ? k : n - 1 - k);
          AddLine(&pts, 5 + spacing * k, 0, step_row + 1);
          AddLine(&pts, 5 + spacing * (k + jump), step_row, 120);
          truth.resize(pts.size(), k);
        }
        PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 160 + int(jump * spacing), 120}, n, PlaneIdOptions{});
        ASSERT_TRUE(id.ok) << id.error;
        EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder) << id.order_error;
        EXPECT_EQ(id.unidentified_segments, 0);
        for (size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(id.points[i].plane, truth[i]) << pts[i].u << "," << pts[i].v;
      }
    }
  }
}

// A depth step along row 50 moves the four stripes 12 px right (sheets 30 px
// apart); the row shows both surfaces' pieces. The lower surface's second
// stripe is hidden from row 40 and starts again only at row 52, so on rows
// 40..50 a piece of the third sheet (at 80) lies alone between the first and
// the fourth. On row 50 it stood between the upper surface's first (32) and
// third (92) stripes with one rank missing, and took sheet 1: 11 points on the
// wrong sheet (the same on a rendered 7-sheet frame at the part's edge, 160 x
// 128). A line that meets more than N segments (here 6), or a numbered sheet
// twice, crosses a step or shows a blob and numbers no piece by position: the
// piece keeps no plane.
TEST(PlaneIdentification, APieceOnAStepsLineIsNotNumberedByPosition) {
  std::vector<StripePoint> pts;
  AddLine(&pts, 20, 0, 51);
  AddLine(&pts, 50, 0, 40);
  AddLine(&pts, 80, 0, 36);
  AddLine(&pts, 80, 40, 51);  // the piece
  AddLine(&pts, 110, 0, 51);
  AddLine(&pts, 32, 50, 120);
  AddLine(&pts, 62, 52, 120);
  AddLine(&pts, 92, 50, 120);
  AddLine(&pts, 122, 50, 120);
  PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 160, 120}, 4, PlaneIdOptions{});
  ASSERT_TRUE(id.ok) << id.error;
  EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder) << id.order_error;
  EXPECT_EQ(id.unidentified_segments, 1);
  for (const auto& p : id.points) {
    const int sheet = p.v < 50 || (p.v == 50 && int(p.u) % 30 == 20) ? int(p.u - 20) / 30 : int(p.u - 32) / 30;
    EXPECT_EQ(p.plane, p.u == 80 && p.v >= 40 ? -1 : sheet) << p.u << "," << p.v;
  }
}

// A depth step along row 95 moves every stripe about one spacing right (34.3
// px, sheets 33.3 apart), so the upper surface's piece of each sheet begins
// within the link distance of the lower surface's piece of the next: the
// connected components join them, and the lines below the step give each
// joined segment the rank of the sheet on their side. Before, the joined
// segment took the number of its longer piece (3/4 of its lines): 50 points
// of the 360 on the wrong sheet. Now the piece whose lines give it another
// rank at the segment's end is cut off and keeps no plane; so does the piece
// of the sheet beyond the last (its lines are those of the cut pieces).
// With the step at row 60 (halves) the joined segments were left whole
// without a plane; now their first pieces are numbered.
TEST(PlaneIdentification, PiecesOfTwoSheetsJoinedAtAStepAreCut) {
  for (int step : {95, 60, 15}) {
    for (double shift : {-1.0, 1.0}) {
      SCOPED_TRACE("step at row " + std::to_string(step) + ", shift " + std::to_string(shift));
      const double spacing = 100.0 / 3;
      std::vector<StripePoint> pts;
      std::vector<int> truth;
      for (int k = 0; k < 3; ++k) {
        AddLine(&pts, 20 + spacing * k, 0, step, 0.02);
        AddLine(&pts, 20 + spacing * (k + 1) + shift, step, 120, 0.02);
        truth.resize(pts.size(), k);
      }
      PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 160, 120}, 3, PlaneIdOptions{});
      ASSERT_TRUE(id.ok) << id.error;
      EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder) << id.order_error;
      int numbered = 0;
      for (size_t i = 0; i < pts.size(); ++i) {
        if (id.points[i].plane < 0) continue;
        ++numbered;
        EXPECT_EQ(id.points[i].plane, truth[i]) << pts[i].u << "," << pts[i].v;
      }
      // Every line's stripes on one side of the step stay numbered.
      EXPECT_GE(numbered, 3 * std::max(step, 120 - step)) << numbered;
    }
  }
}

// No line meets all N sheets: an inner sheet is missing on the upper rows,
// another on the lower ones. Each line still spans the N sheets, its stripes
// a whole number of spacings apart (one or two, adding up to N - 1), so the
// spacings fix each stripe's sheet. Before, the frame was refused (and the
// edge chains, which need every sheet at the top edge, could not number it).
// Where the lines could be either end's N - 1 sheets (one end's stripe never
// seen, or the first end's on some rows and the last end's on the others),
// nothing is numbered.
TEST(PlaneIdentification, LinesSpanningTheSheetsWithOneMissingNumberThem) {
  for (int n = 4; n <= 6; ++n) {
    SCOPED_TRACE(std::to_string(n) + " sheets");
    const double spacing = 120.0 / n;
    std::vector<StripePoint> pts;
    for (int k = 0; k < n; ++k) AddLine(&pts, 20 + spacing * k, k == 1 ? 60 : 0, k == n - 2 ? 60 : 120, 0.05);
    PlaneIdentification id = IdentifyPlanes(pts, {0, 0, 160, 120}, n, PlaneIdOptions{});
    ASSERT_TRUE(id.ok) << id.error;
    EXPECT_EQ(id.method, PlaneIdMethod::kStripeOrder) << id.order_error;
    EXPECT_EQ(id.unidentified_segments, 0);
    for (const auto& p : id.points) {
      EXPECT_EQ(p.plane, int(std::lround((p.u - 0.05 * p.v - 20) / spacing))) << p.u << "," << p.v;
    }
    for (bool alternate : {false, true}) {
      pts.clear();
      for (int k = 0; k < n; ++k) {
        if (alternate) {
          AddLine(&pts, 20 + spacing * k, k == 0 ? 60 : 0, k == n - 1 ? 60 : 120);
        } else if (k < n - 1) {
          AddLine(&pts, 20 + spacing * k, k == 0 ? 20 : 0, 120);
        }
      }
      PlaneIdentification ambiguous = IdentifyPlanes(pts, {0, 0, 160, 120}, n, PlaneIdOptions{});
      for (const auto& p : ambiguous.points) EXPECT_EQ(p.plane, -1) << alternate << ": " << p.u << "," << p.v;
    }
  }
}

}  // namespace
}  // namespace lt::test

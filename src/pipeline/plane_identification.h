// Multi-line laser plane identification: which of N laser sheets produced each
// stripe point. Points are joined into segments (connected components over
// adjacent search lines) and numbered by two methods:
//
// Stripe order (first): sheets from one projector do not cross in the image, so
// on a search line that meets exactly N stripes they are the N sheets in image
// order, and each segment there gets a vote for its rank. A segment takes the
// rank that holds at least 3/4 of its votes (not on lines whose neighbouring
// stripes stand far closer or farther apart than the median spacing of such
// lines: one sheet seen twice at a depth step; nor on lines that give a numbered
// segment another rank: a blob where a sheet is hidden). A segment that those
// lines give another rank only at one end is two sheets' pieces joined at a
// depth step: the piece there is cut off without a plane. Where no line meets
// all N, lines whose stripes stand whole spacings apart spanning all N sheets
// (the missing ones between them) take their place. A segment that is never
// on such a line takes the rank its position calls for on lines where it lies
// between numbered segments (or the line's ends) with exactly the missing ranks
// between them (not on lines meeting more than N segments or a numbered sheet
// twice: a depth step's two surfaces, or a blob). Segments neither step decides keep no plane (not guessed); on
// every line the numbered stripes must then be in increasing order (one sheet
// may meet a line twice where its stripe jumps at a depth step and one piece
// hands over to the next; pieces numbered by votes may stand reversed beside a
// thin wall), a piece numbered by its position that breaks it keeps no plane,
// as does one with more other sheets' stripes beside it on a line than its
// number leaves room for (plane_id_room.h; such lines at a numbered
// segment's end also mark it as joined there).
// It needs one search line that meets all N stripes, and no stripe to reach an
// image edge.
//
// Edge chains (when the order cannot decide; thesis section 2.1.3, after the
// method of its reference [9]): segments are classified by the image edges they
// touch, chained into one group per sheet by shortest connection vectors from
// the start edge, and groups are numbered across the image. It needs every
// sheet to reach the start edge.
//
// When neither can decide, identification fails with both reasons.
//
// Edges: the stripes run along the search direction's normal, from a start edge
// to an end edge. Searching rows (stripes run top to bottom) the start edge is
// the top row and the end edge the bottom row, and planes are numbered left to
// right; searching columns, start = left, end = right, numbered top to bottom.
// The thesis's "left" and "right" edge types (LEC, REC) are the start and end
// edges here.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "pipeline/extraction_options.h"
#include "pipeline/stripe_point.h"

namespace lt {

enum class SegmentType {
  kFloating,   // F: touches neither edge
  kStartEdge,  // LEC: touches the start edge
  kEndEdge,    // REC: touches the end edge
  kBothEdges,  // LREC: runs from edge to edge
};
const char* SegmentTypeName(SegmentType type);  // "F", "LEC", "REC", "LREC"

struct PlaneIdOptions {
  SearchAxis axis = SearchAxis::kRows;
  // Points on adjacent search lines are connected when their positions across
  // differ by at most this (pixels). 1 on integer positions is 8-connectivity;
  // the default also links stripes tilted up to ~60 degrees.
  double link_distance = 2.0;
  // A segment with a point at most this far (pixels) from the start/end edge
  // is connected to that edge.
  int edge_margin = 5;
  // Segments with fewer points are noise: no plane, and not required to join.
  int min_segment_points = 5;

  void Check() const;  // throws lt::InputError
};

struct StripeSegment {
  SegmentType type = SegmentType::kFloating;
  std::vector<int> points;  // indices into the input points, by search line
  int plane = -1;           // -1: ignored (too small) or not identified
  bool ignored = false;     // fewer than min_segment_points
};

enum class PlaneIdMethod {
  kStripeOrder,  // the stripes' order across the image
  kEdgeChains,   // the thesis's chains from the start edge (the order could not decide)
};

struct PlaneIdentification {
  bool ok = false;
  std::string error;                // why identification failed (empty when ok)
  PlaneIdMethod method = PlaneIdMethod::kStripeOrder;
  std::string order_error;          // with kEdgeChains: why the order could not decide
  int unidentified_segments = 0;    // segments (not noise) left without a plane
  int groups_found = 0;             // chains the edge method started
  int lines_of_fewer_stripes = 0;   // when !ok: lines of fewer stripes than sheets, which nothing decided
  std::vector<StripePoint> points;  // the input, with `plane` set when ok
  std::vector<StripeSegment> segments;  // pieces cut off a joined segment come last
};

// Whether stripe points of one search line, each with a candidate rank in
// `plane` (0..N-1 across the image), lie where the scanner measures: its
// working range (scan: SheetsOfRanks::RanksFit, pipeline/plane_id_sheets.h).
// A stripe tried as two neighbouring sheets' light (facing projectors' sheets
// cross) stands twice, at one position, with consecutive ranks.
using RankFit = std::function<bool(const std::vector<StripePoint>& points)>;

// `region` is the rectangle that was searched (the image or its ROI), in the
// points' coordinates. n_planes >= 1. With `range_fit`, a search line of
// fewer stripes than sheets (whose stripes could be several sets of the
// sheets: N - 1 one spacing apart, either end's) is read as a line meeting
// all N when exactly one numbering of its stripes fits (every increasing
// numbering is tried, and each stripe also as two sheets' light) and it reads
// each stripe as one sheet; without it, or when several fit, such a line
// numbers nothing by itself.
PlaneIdentification IdentifyPlanes(const std::vector<StripePoint>& points, const PixelRect& region, int n_planes,
                                   const PlaneIdOptions& options, const RankFit& range_fit = {});

}  // namespace lt

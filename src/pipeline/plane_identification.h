// Multi-line laser plane identification (thesis section 2.1.3, after the
// method of its reference [9]): which of N laser sheets produced each stripe
// point. Points are joined into segments (connected components), segments are
// classified by the image edges they touch, chained into one group per sheet by
// shortest connection vectors, and groups are numbered across the image. When
// the frame does not yield exactly N groups that use every segment, it says so
// instead of guessing.
//
// Edges: the stripes run along the search direction's normal, from a start edge
// to an end edge. Searching rows (stripes run top to bottom) the start edge is
// the top row and the end edge the bottom row, and planes are numbered left to
// right; searching columns, start = left, end = right, numbered top to bottom.
// The thesis's "left" and "right" edge types (LEC, REC) are the start and end
// edges here.
#pragma once

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

struct PlaneIdentification {
  bool ok = false;
  std::string error;                // why identification failed (empty when ok)
  std::vector<StripePoint> points;  // the input, with `plane` set when ok
  std::vector<StripeSegment> segments;
  int groups_found = 0;
};

// `region` is the rectangle that was searched (the image or its ROI), in the
// points' coordinates. n_planes >= 1.
PlaneIdentification IdentifyPlanes(const std::vector<StripePoint>& points, const PixelRect& region, int n_planes,
                                   const PlaneIdOptions& options);

}  // namespace lt

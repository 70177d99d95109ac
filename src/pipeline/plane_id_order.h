// Plane identification by the stripes' order across the image: the first of
// IdentifyPlanes's two methods (pipeline/plane_identification.h), internal to it.
#pragma once

#include <string>
#include <vector>

#include "pipeline/plane_id_range.h"
#include "pipeline/plane_identification.h"

namespace lt {

// A segment's first and last search line, and its mean position across on each.
struct SegmentEnds {
  double first_along = 0, first_across = 0;
  double last_along = 0, last_across = 0;
};

// Each point's position along the search direction (its search line, rounded)
// and across it, and its stripe's width (pixels), by point index.
struct PointAxes {
  std::vector<double> along, across, width;
};

// What the stripes' order gives: a plane per segment (-1: none), and per
// segment the search line from which on (cut_after) or up to which (cut_before)
// its points belong to another sheet (NaN: none).
struct StripeOrderPlanes {
  std::vector<int> planes;  // empty when the order cannot decide (see error)
  std::vector<double> cut_before, cut_after;
  std::string error;
  int lines_of_fewer = 0;  // with the error: lines of fewer stripes than sheets, which no reading decided
};

// The plane of each of the candidate segments by the stripes' order (the
// header's steps 1-3); `unnumbered` segments stand on the lines but take no
// plane (pieces cut off an earlier reading). With `fit` (the scanner's
// working range), lines of fewer stripes than sheets that it leaves one
// numbering (plane_id_range.h) are read as lines meeting all N.
StripeOrderPlanes PlanesByStripeOrder(const std::vector<StripeSegment>& segments, const std::vector<int>& candidates,
                                      const std::vector<char>& unnumbered, const std::vector<SegmentEnds>& ends,
                                      const PointAxes& axes, int n_planes, const LineFit& fit = {});

}  // namespace lt

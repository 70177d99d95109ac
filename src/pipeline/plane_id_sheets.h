// The laser planes of the stripes plane identification numbers: it gives each
// stripe its rank among the N sheets across the image (0..N-1, left to right
// searching rows, top to bottom searching columns), and a rank is a plane once
// the sheets' image order is known.
//
// One projector's sheets (a diffractive element's fan) keep one image order at
// every depth, and each rank is one plane (PlanesInImageOrder). The sheets of
// projectors on opposite sides of the camera (facing lasers) move across the
// image in opposite directions as the depth changes, and pass each other where
// they cross: beyond that depth two of them swap ranks. Then, on each search
// line, every order the sheets take over depths from 1 mm to 1 km (each over
// the depths where it holds) is tried: it fits when each of the line's ranked
// points, on the plane the order gives its rank, lies in front of the camera
// at a depth where the order holds, give or take 0.5 px of the stripe's
// position (the surface at about one depth across the line, as reading ranks
// from the image order assumes), and puts no stripe measured apart from the
// others where two sheets meet (within 1.5 px). A point's plane is the one
// every fitting order gives its rank; it keeps none when no order fits, when
// fitting orders differ for it (an image of a surface on one side of a
// crossing that reads as well as one on the other side), or when another
// stripe is measured, or another sheet stands in a fitting order, within 3 px
// of it (two sheets' light in one stripe, or stripes whose order a fraction
// of a pixel's error may swap).
//
// A scanner's working range (its datasheet's measuring range, camera z) is
// where its stripes' order is known: given one, only the orders the sheets
// take at depths within it are tried, an order fits only points at depths
// within it (give or take the 0.5 px), and a point whose depth on the plane
// it would take lies outside it keeps no plane. Light from a surface outside
// the range that reads exactly as a surface inside it (mirror-image rigs)
// cannot be told apart: the range is a promise about where the surfaces are.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/extraction_options.h"
#include "pipeline/stripe_point.h"
#include "pipeline/triangulation.h"

namespace lt {

// Depths (camera z, metres) where the scanner measures: near_m < far_m, both > 0.
struct DepthRange {
  double near_m = 0, far_m = 0;
  void Check(const std::string& where) const;  // throws lt::InputError(where, ...)
};
// "MIN_MM:MAX_MM" (millimetres, e.g. "60:120"); throws lt::InputError(where, ...).
DepthRange ParseDepthRange(const std::string& text, const std::string& where);

class SheetsOfRanks {
 public:
  // The triangulator's planes (camera frame), the axis the stripes were
  // searched along, and the depths where the scanner measures (none: 1 mm to
  // 1 km, every point kept that one order fits).
  SheetsOfRanks(const Triangulator& triangulator, SearchAxis axis, std::optional<DepthRange> range = {});

  // Whether the sheets' image order changes with depth in front of the camera.
  bool depth_dependent() const { return depth_dependent_; }

  // Each point's rank (plane >= 0) becomes its plane, or -1 where the rank
  // fits no plane or more than one, or (with a range) puts the point outside
  // the range; returns how many ranked points were left without a plane so.
  int Apply(std::vector<StripePoint>* points) const;

  // Whether the points of one search line, each with a candidate rank in
  // `plane`, lie within the depth range on the sheets those ranks give (for
  // facing projectors: in one order the sheets take there), give or take
  // 0.5 px of their positions, as Apply's orders fit. Two points at one
  // position (a stripe read as two sheets' light) fit where both sheets
  // stand within half the stripe's width (at least 1.5 px) of it at one
  // depth within the range.
  // How plane identification reads a line of fewer stripes than sheets
  // (IdentifyPlanes's range_fit; scan uses it where !depth_dependent(): with
  // facing projectors a stripe of two crossing sheets' light, which the
  // stripes' order counts as one, numbered a neighbour by position wrong);
  // without a range, true wherever the ranks are sheets in front of the
  // camera.
  bool RanksFit(const std::vector<StripePoint>& points) const;

 private:
  const Triangulator& triangulator_;
  SearchAxis axis_;
  bool ranged_ = false;     // a depth range was given
  double w_min_, w_max_;    // inverse depths (1/m) where the sheets' orders are read
  std::vector<int> order_;  // plane of each rank, at the planes' reference depth
  bool depth_dependent_ = false;
};

}  // namespace lt

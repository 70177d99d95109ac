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
#pragma once

#include <vector>

#include "pipeline/extraction_options.h"
#include "pipeline/stripe_point.h"
#include "pipeline/triangulation.h"

namespace lt {

class SheetsOfRanks {
 public:
  // The triangulator's planes (camera frame) and the axis the stripes were searched along.
  SheetsOfRanks(const Triangulator& triangulator, SearchAxis axis);

  // Whether the sheets' image order changes with depth in front of the camera.
  bool depth_dependent() const { return depth_dependent_; }

  // Each point's rank (plane >= 0) becomes its plane, or -1 where the rank
  // fits no plane or more than one; returns how many ranked points were left
  // without a plane so.
  int Apply(std::vector<StripePoint>* points) const;

 private:
  const Triangulator& triangulator_;
  SearchAxis axis_;
  std::vector<int> order_;  // plane of each rank, at the planes' reference depth
  bool depth_dependent_ = false;
};

}  // namespace lt

// Internal to checkerboard corner detection (pipeline/calib_corners.cpp and the
// pipeline/calib_corner_*.cpp files that hold its parts), not an API: use
// DetectCheckerboard (pipeline/calib_corners.h).
// The detection at one smoothing scale: contrast, saddle candidates, the grid,
// the board's order and colours, the corners with their standard deviations.
#pragma once

#include "core/image.h"
#include "pipeline/calib_checkerboard.h"
#include "pipeline/calib_corner_candidates.h"
#include "pipeline/calib_corner_grid.h"
#include "pipeline/calib_corners.h"

namespace lt {
namespace corner_detail {

struct ScaleResult {
  CornerDetection det;
  Failure failure = Failure::kNone;
  ContrastFloor floor;  // the contrast floor of this scale's corners
};

// The detection at one smoothing scale, on the image already averaged to one
// channel and with its noise estimated.
ScaleResult DetectAtScale(const Image<float>& img, double noise, const CheckerboardSpec& board,
                          const CornerDetectionOptions& options, double sigma);

}  // namespace corner_detail
}  // namespace lt

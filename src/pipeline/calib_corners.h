// Checkerboard corner detection with subpixel refinement (docs/calibration.md).
//
//  1. Saddle response: the image smoothed by a Gaussian of sigma_px (kernels
//     integrated over each pixel, pipeline/gaussian_filter.h) has a saddle at
//     each X-junction of the board; S = r_xy² − r_xx·r_yy (the negated Hessian
//     determinant) peaks there. Local maxima of S above min_response of an
//     ideal corner of their own contrast (the range on the validation circle,
//     at least 3 noise σ and a tenth of the light on the corner, its brightest
//     value there above the image's dark level) are candidates: uneven light
//     does not matter.
//  2. Subpixel: Newton's method on the gradient of the smoothed image,
//     evaluated exactly at subpixel positions, converges to its saddle point
//     (the local quadratic model of the smoothed image is fitted afresh at
//     each step). An X-junction of two straight edges is point-symmetric about
//     the corner, so the saddle of its smoothed image is the corner itself,
//     whatever the angle between the edges (perspective).
//  3. Validation: on a circle around the saddle the smoothed image must change
//     between dark and bright exactly four times, at two pairs of nearly
//     opposite angles (the two edges through the corner).
//  4. Grid: from a seed corner, neighbours are found along its two edge
//     directions (of two very unequally far along one edge, the farther is
//     dropped: another object's corner beyond the board's edge), then the
//     grid grows by predicting each next corner from the two before it (or
//     from a parallelogram of three) and taking the nearest
//     candidate within neighbour_tolerance of the local spacing. A grid
//     larger than the board loses the outer corners beyond the squares
//     (their cells on the outer side not a black and a white square). On a
//     complete board every corner must lie where the homography through its
//     neighbours puts it (within 0.35 px and 6 predicted standard deviations,
//     or a tenth of the local spacing): a point that took a lost corner's
//     place (a saddle of noise in a JPEG's square beside it) is replaced by
//     the saddle found from that prediction (where two such points lie side
//     by side, from the prediction of its neighbours on the grid), or the
//     board is refused, naming the corner.
//  5. Order: the grid must be complete and rows x cols (or cols x rows); the
//     board's orientation follows from the colour convention of
//     pipeline/calib_checkerboard.h (rows + cols odd; a symmetric board comes
//     out in one of the orders of its turned frames).
//
// Refusals (ok = false, with the reason): no contrast, no grid, a grid other
// than rows x cols (a partly visible or occluded board: `grid` then holds the
// corners found, in the grid's own indices), or colours that do not tell the
// board's orientation (each square compared with its neighbours). Inverted
// contrast is the board turned by half a turn: the corners come out in that
// order. Corners are required at least 2·sigma_px + 2 pixels
// inside the image (the smoothing kernel needs the image around them), so a
// board that touches the image border is refused as partly visible.
//
// Scale: when the board is not found at sigma_px because of too few corners,
// no grid, or an incomplete grid that another scale could complete (holes,
// squares small against the kernel, a grid cut short inside the image), the
// detection is repeated at 2 and 3 times sigma_px and at 1/1.5 and 1/2.25 of
// it (within [0.7, 5]); the first complete board whose colours confirm its
// order is returned, with the scale in `sigma_px`, once its corners pass
// checks against an occluder that a larger kernel averages into a saddle:
// each where the homography through its neighbours puts it and about as
// sharp as they are; from a larger scale also point-symmetric and a saddle
// at the requested scale. A grid larger than the
// board, or a complete-looking smaller grid with large squares whose next
// corners would lie well inside the image (a board of another size), no
// contrast, and ambiguous colours are refused at once. When every scale
// fails, the reason (and grid) is that of the requested scale, with the
// other scales named, unless the board is found on the image halved (a 2 x 2
// mean, recursively while at least 128 px a side are left: a large photograph
// out of focus beyond the ladder's largest scale), its corners then refined on
// the image by Newton's method at twice the scale they were found at.
//
// Each corner comes with its predicted standard deviation from the image
// noise (estimated from the image, Immerkær's operator with a median) through
// the refinement: Cov = σ_n² c H⁻¹H⁻ᵀ, with H the Hessian at the saddle and
// c the squared norm of the derivative kernel.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/image.h"
#include "pipeline/calib_camera.h"
#include "pipeline/calib_checkerboard.h"

namespace lt {

struct CornerDetectionOptions {
  double sigma_px = 1.5;             // Gaussian smoothing (pixels), in [0.7, 5]
  double min_response = 0.15;        // candidate threshold, fraction of an ideal corner's response, in (0, 1)
  double neighbour_tolerance = 0.3;  // fraction of the local corner spacing, in (0, 0.5)
  int max_seeds = 20;                // seed corners tried before giving up
  // When the board is not found at sigma_px for a reason another scale may
  // cure (too few corners, no grid, a grid with holes or cut short), try
  // 2 and 3 times sigma_px, then 1/1.5 and 1/2.25 of it (within [0.7, 5]),
  // and take the first complete board.
  bool other_scales = true;

  // Throws lt::InputError ("option <name>: ...").
  void Check() const;
};

struct GridCorner {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  int i = 0, j = 0;  // board row and column when ok; the grid's own indices otherwise
};

struct CornerDetection {
  bool ok = false;
  std::string reason;  // why the board was not found (empty when ok)
  // When ok: rows·cols corners, row-major in board order (index i·cols + j).
  std::vector<Eigen::Vector2d> corners;
  std::vector<double> corner_std_px;  // predicted standard deviation per axis of each corner
  std::vector<GridCorner> grid;       // the corners of the largest grid found
  double noise_sigma = 0;             // image noise estimate (image units)
  double contrast = 0;                // 99.9th − 0.1st percentile of the smoothed image (image units)
  int candidates = 0;                 // validated saddle points
  double sigma_px = 0;                // the smoothing scale of the result (the requested one when refused)
  int other_scales_tried = 0;         // scales tried after the requested one failed (0: found at sigma_px)
};

// One-channel images, or several channels averaged. Throws lt::InputError for
// invalid options or board, or an empty image.
template <typename T>
CornerDetection DetectCheckerboard(const ImageView<T>& image, const CheckerboardSpec& board,
                                   const CornerDetectionOptions& options = {});
CornerDetection DetectCheckerboard(const AnyImage& image, const CheckerboardSpec& board,
                                   const CornerDetectionOptions& options = {});

// The calibration view of a complete detection (detection.ok): the board's
// corner points (target frame) with their pixels, in board order.
CalibrationView ViewOfDetection(const CheckerboardSpec& board, const CornerDetection& detection);

}  // namespace lt

// The calibration checkerboard: its geometry, its colour convention (which
// fixes the order of the corners), and a synthetic image of it seen through a
// camera, for tests and benchmarks of detection and calibration.
//
// Board frame (OpenCV's): the origin is the first inner corner, x runs along a
// row of corners (column index j), y down the columns (row index i), z into the
// board (away from a viewer of the printed side). Inner corner (i, j) is at
// (j·s, i·s, 0). The squares cover x in [−s, cols·s], y in [−s, rows·s]; the
// square with corners (i, j) and (i + 1, j + 1) is black when i + j is even,
// so the corner square next to the origin, (−1, −1), is black. A white margin
// of `margin_squares` squares surrounds the squares.
//
// Orientation. When rows + cols is odd (one even, one odd: e.g. 7 x 10 inner
// corners, 8 x 11 squares), rows != cols, so the two grid directions are told
// apart by their lengths, and the square at the far corner (rows − 1, cols − 1)
// is white while the one at the origin is black, so a half turn of the board
// is told apart by colour. A board seen from the back (a mirror image) cannot
// occur; seen from the front, the corners come out in the same board order
// whatever the camera's roll.
//
// A symmetric board (rows + cols even, e.g. OpenCV's 9 x 6; a square one also
// looks the same after a quarter turn) is detected too, with its corners in
// one of the orders of a frame turned by a half (or quarter) turn about the
// board's centre: a right-handed board frame, but not the same one in every
// view. That is enough for the camera's intrinsics (each view has its own
// pose) and for laser planes (the board's plane and area are the same); the
// hand-eye step, which needs one board frame in every view (the board is fixed
// in the world), chooses each view's turn from the robot's motion
// (pipeline/calib_board_turns.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/pose.h"
#include "sensor/camera.h"

namespace lt {

struct CheckerboardSpec {
  int rows = 7;    // inner corners down a column
  int cols = 10;   // inner corners along a row
  double square_m = 3e-3;
  int margin_squares = 1;  // white border, in squares (the detector needs at least 1)

  // Throws lt::InputError ("option <name>: ...") unless rows, cols >= 2,
  // square_m > 0 and margin_squares >= 0.
  void Check() const;
  // A half or quarter turn about its centre maps the board onto itself (rows + cols even).
  bool Symmetric() const { return (rows + cols) % 2 == 0; }
  int CornerCount() const { return rows * cols; }
  // Inner corners in the board frame, row-major: index i·cols + j.
  std::vector<Eigen::Vector3d> CornerPoints() const;
  // What lies at board point (x, y): 0 black, 1 white (squares or margin),
  // -1 off the board.
  int ColourAt(double x, double y) const;
};

struct SyntheticBoardOptions {
  double black = 0.1, white = 0.9;  // image units
  double background = 0.45;         // off the board
  double noise_sigma = 0;           // additive Gaussian noise (image units)
  int supersampling = 16;           // n x n stratified, jittered samples in each pixel an edge crosses
  uint64_t seed = 1;
};

// One-channel float image of the board at cam_from_board, each pixel the mean
// of the board over its area: the board coordinates of the pixel corners are
// exact (Camera::Unproject, so distortion included), those of the samples
// inside a pixel bilinear between them (an error of second order in the pixel
// size); pixels whose four corners lie in one square take its colour directly.
Image<float> RenderCheckerboard(const Camera& camera, const Pose& cam_from_board, const CheckerboardSpec& board,
                                const SyntheticBoardOptions& options = {});

}  // namespace lt

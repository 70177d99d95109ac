// Internal to checkerboard corner detection (pipeline/calib_corners.cpp and the
// pipeline/calib_corner_*.cpp files that hold its parts), not an API: use
// DetectCheckerboard (pipeline/calib_corners.h).
// The grid of corners: growing it from a seed candidate, why a scale refused
// the board (and whether another scale may cure it), and how far a detected
// corner lies from where its neighbours put it.
#pragma once

#include <Eigen/Core>
#include <map>
#include <utility>
#include <string>
#include <vector>

#include "pipeline/calib_checkerboard.h"
#include "pipeline/calib_corner_candidates.h"

namespace lt {
namespace corner_detail {

using Cell = std::pair<int, int>;

struct Grid {
  std::map<Cell, int> cells;  // (a, b) -> candidate
};

// The grid grown from candidate `seed` along its edges, each next corner the
// nearest candidate within `tolerance` of the local spacing of its prediction.
Grid GrowGrid(const std::vector<Candidate>& cands, int seed, double tolerance);

// The cells a grid spans: rows a0.. and columns c0.. of its own indices, how
// many of each, and whether every cell of that rectangle holds a corner.
struct GridExtent {
  int a0 = 0, c0 = 0, rows = 0, cols = 0;
  bool full = false;
  // Its rectangle is at most the board's, either way round.
  bool FitsIn(const CheckerboardSpec& board) const {
    return (rows <= board.rows && cols <= board.cols) || (rows <= board.cols && cols <= board.rows);
  }
  // Its rectangle is the board's, either way round.
  bool Matches(const CheckerboardSpec& board) const {
    return (rows == board.rows && cols == board.cols) || (rows == board.cols && cols == board.rows);
  }
};
GridExtent Extent(const Grid& g);

// Drops from g the corners of its outermost lines that lie beyond the board's
// squares: a corner whose two cells on the outer side (centred half a grid
// step out and half a step either way along the line) do not differ in colour
// as a board's do: opposite to the two cells on its inner side, by at least
// half their difference and the contrast floor. Every inner corner of a board
// has a black and a white square on each side, diagonally opposite. A margin narrower than the validation circle
// against a dark background makes X-like points one step beyond the outer
// corners (the outermost square, the margin and the background change four
// times on the circle); their outer side is margin and background, one
// colour along the line. Repeated until no corner is dropped.
void DropCornersBeyondSquares(Grid* g, const std::vector<Candidate>& cands, const Smoothed& sm,
                              const ContrastFloor& floor);

// Why one scale refused the board: the first three after kNone are what another scale may
// cure (blur, squares small against the kernel); the others no scale cures.
enum class Failure { kNone, kFewCandidates, kNoGrid, kIncompleteGrid, kNoContrast, kGridNotTheBoard, kColours };

// Why the incomplete grid g is not the board: kIncompleteGrid when another
// scale may complete it, kGridNotTheBoard when none can.
Failure GridFailure(const Grid& g, const std::vector<Candidate>& cands, const CheckerboardSpec& board, int w, int h,
                    double border, double circle);

// The image's edges ("left", "right", "top", "bottom", in that order, joined
// by " and ") beyond which the grid's next corners would lie: a step on from
// a corner with a neighbour on one side and none on the other falls within
// `border` of that edge or beyond it. Empty when none does.
std::string EdgesTheGridRunsOff(const Grid& g, const std::vector<Candidate>& cands, int w, int h, double border);

// Where the homography through the neighbours of corner (i, j) of a rows x
// cols detection (those within one step, or two when fewer than 5) puts it;
// false when there are too few neighbours or the homography is degenerate.
// Corners k with (*left_out)[k] set are not used.
bool GridPrediction(const std::vector<Eigen::Vector2d>& corners, int rows, int cols, int i, int j,
                    Eigen::Vector2d* predicted, const std::vector<char>* left_out = nullptr);
// How far corner (i, j) of a rows x cols detection lies from where the
// homography through its neighbours puts it (0 with too few neighbours).
double OffGrid(const std::vector<Eigen::Vector2d>& corners, int rows, int cols, int i, int j);

}  // namespace corner_detail
}  // namespace lt

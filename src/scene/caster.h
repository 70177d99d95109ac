// How the scanner turns about the nozzle while it follows a toolpath: a heading
// angle in the bed plane over time, by one of four rules.
//
//   fixed    the heading stays 0 (the G-code +x axis).
//   heading  the direction of the current move (its tangent on arcs). At a corner
//            between two straight moves the heading jumps: an end effector would
//            have to turn infinitely fast there.
//   caster   the "virtual caster": like a caster wheel trailing behind its pivot, the
//            heading is the mean of the unit direction vectors of the path over a
//            window of path length w behind the nozzle. Averaging unit vectors (not
//            angles) is safe across the +-180 degree wrap. The mean of the unit
//            tangent over path length is the chord from the point w behind to the
//            nozzle divided by w, so the caster heading is the direction of that chord,
//            computed exactly. Near the start (less than w travelled) the window is
//            the path so far. Where the path doubles back the chord passes through
//            zero length and the heading swings by up to 180 degrees at once.
//   trailing a wheel trailing the nozzle at distance w (scene/trailing_wheel.h): the
//            heading turns towards the path's direction at rate v sin(angle off the
//            path) / w, never faster than v / w, reversals included; it lags behind
//            the caster on corners. A reversal leaves the wheel pointing straight
//            back, a balance it would keep forever on a straight move; it is taken
//            as 1 degree off (towards the side it came from), so the wheel swings
//            round within about 5 w of path, as a real one does.
//
// Any rule can be limited to a largest turn rate (`max_turn_rad_s`, scene/turn_rate_limit.h):
// the heading then follows the rule's where it turns no faster, and turns at the limit,
// the short way round, where the rule turns faster (corners, a caster's swing), until it
// has caught up. An arm's wrist turns no faster than its joint speed. A winding limit
// (`max_winding_rad`) also bounds how far the heading winds from its start: a print that
// loops one way would wind the wrist past its range, so the scanner unwinds a whole
// turn, the other way round, at the turn rate limit, where it would pass the bound, or
// earlier, on a move that lays no bead, once it has wound more than half a turn.
//
// Path length here is measured in the bed plane: moves without motion in that plane
// (z only, extruder only, dwells) keep the heading. Travel moves count like printing
// moves: the scanner turns with the nozzle whatever it does. Before any motion in the
// bed plane the heading is that of the first such move; a path without any has
// heading 0.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scene/toolpath.h"
#include "scene/turn_rate_limit.h"

namespace lt {

enum class OrientationMode { kFixed, kHeading, kCaster, kTrailing };

struct OrientationOptions {
  OrientationMode mode = OrientationMode::kCaster;
  double caster_window_m = 0.010;  // path length behind the nozzle averaged by the caster
  double trail_m = 0.010;          // the trailing wheel's distance behind the nozzle
  double max_turn_rad_s = 0;       // the heading's largest turn rate; 0: no limit
  // How far the heading may wind either way from where it starts (an arm's wrist
  // range, less a margin); beyond it the scanner unwinds a whole turn at
  // max_turn_rad_s. Infinite: no limit; else >= pi and needs max_turn_rad_s.
  double max_winding_rad = std::numeric_limits<double>::infinity();
  // Throws std::invalid_argument unless the window and the trail are finite and > 0,
  // the turn rate limit is finite and >= 0, and the winding limit as above.
  void Check() const;
};

// "fixed", "heading", "caster", "trailing" and back (ParseOrientationMode throws
// std::invalid_argument on any other name).
std::string OrientationModeName(OrientationMode mode);
OrientationMode ParseOrientationMode(const std::string& name);

// How fast the heading turns along a path.
struct TurnRates {
  // Largest |d heading / dt| where the heading changes continuously, and when.
  double max_rate_rad_s = 0;
  double max_rate_time_s = 0;
  // Instantaneous changes of heading (corners in heading mode): how many exceed
  // 1e-9 rad, the largest, when and at which G-code line the new move starts.
  size_t jumps = 0;
  double max_jump_rad = 0;
  double max_jump_time_s = 0;
  int max_jump_line = 0;
  // With a turn rate limit: how often the heading turns at the limit, behind the
  // rule's, the longest such slew (s) and when it starts.
  size_t slews = 0;
  double longest_slew_s = 0;
  double longest_slew_time_s = 0;
  // With a winding limit: the slews that unwind, and the farthest the heading winds
  // from its start (rad).
  size_t unwinds = 0;
  double max_winding_rad = 0;

  double MaxRateDegS() const;
  double MaxJumpDeg() const;
};

class ToolpathOrientation {
 public:
  // Throws std::invalid_argument when the options fail Check().
  ToolpathOrientation(std::shared_ptr<const Toolpath> path, OrientationOptions options);

  const OrientationOptions& options() const { return options_; }
  const Toolpath& path() const { return *path_; }

  // The heading at time t (clamped to the path's duration): the unit direction in
  // the bed plane, and its angle counter-clockwise from +x in (-pi, pi].
  Eigen::Vector2d DirectionAt(double t_s) const;
  double HeadingAt(double t_s) const;

  // The turn rates along the whole path. Caster: exact on pieces where the nozzle
  // and the window's tail are both on straight moves (the rate then peaks where the
  // chord is shortest, a closed form); sampled at 17 points on pieces with arcs.
  // Trailing: exact on straight moves (the angle off the path shrinks monotonically);
  // on arcs sampled at steps over which the angle turns by at most 0.05 rad.
  // With a turn rate limit: the limit where the heading slews, else the rule's
  // largest change over a 1 ms step.
  TurnRates ComputeTurnRates() const;

  // Path length in the bed plane travelled by time t, and the point in that plane at
  // path length s (clamped to the path).
  double PathLengthAt(double t_s) const;
  Eigen::Vector2d PointAtLength(double s_m) const;
  double TotalLength() const { return total_xy_m_; }

 private:
  // Index (into path_->segments) of the segment with motion in the bed plane that
  // holds path length s; the first such segment for s <= 0.
  size_t SegmentAtLength(double s_m) const;
  // The heading of the move at time t (heading mode).
  Eigen::Vector2d MoveDirectionAt(double t_s) const;
  // The rule's heading, without the turn rate limit.
  Eigen::Vector2d RuleDirectionAt(double t_s) const;
  double RuleHeadingAt(double t_s) const;
  Eigen::Vector2d CasterDirectionAt(double s_m, size_t segment) const;
  // The trailing wheel on segment k (with motion in the bed plane) at path length s.
  Eigen::Vector2d TrailingDirectionAt(double s_m, size_t segment) const;
  double TrailingAngleOffPath(double s_m, size_t segment) const;
  double CurvatureOf(size_t segment) const;
  void StartTrailingWheel();

  TurnRates HeadingTurnRates() const;
  TurnRates CasterTurnRates() const;
  TurnRates TrailingTurnRates() const;

  std::shared_ptr<const Toolpath> path_;
  OrientationOptions options_;
  std::vector<double> s_start_m_;   // bed-plane path length at the start of each segment
  std::vector<size_t> xy_segments_; // indices of segments with motion in the bed plane
  double total_xy_m_ = 0;
  // Trailing mode: the wheel's half-angle vector (scene/trailing_wheel.h) at the start
  // of each segment with motion in the bed plane.
  std::vector<Eigen::Vector2d> wheel_start_;
  // How far the heading jumps at the start of each segment (rad): 0 but where the
  // path doubles back and the wheel is taken a little off straight back.
  std::vector<double> wheel_jump_rad_;
  std::optional<TurnRateLimit> limit_;
};

}  // namespace lt

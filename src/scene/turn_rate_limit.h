// A heading that follows another but never turns faster than a given rate, as an
// arm's wrist would: where the followed heading turns slower it is that heading;
// where it turns faster (a corner, a caster's swing where the path doubles back)
// this one turns at the limit, the short way round, until it has caught up.
//
// Built by stepping the followed heading at `step_s` (1 ms): a step that needs more
// than rate x step starts (or continues) a slew at the limit; a slew ends where it
// meets the followed heading, found by bisection within the step to 1e-9 s. So the
// heading is continuous, follows exactly where it follows, and a slew starts at most
// one step late. Stored as pieces (following, or slewing from an angle), not samples.
// Optionally it also bounds how far the scanner winds from where it started.
#pragma once

#include <functional>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace lt {

class TurnRateLimit {
 public:
  // `followed(t)`: the heading to follow, an angle in radians, over [t_begin, t_end].
  // Throws std::invalid_argument unless max_rate_rad_s and step_s are finite and > 0
  // and t_end >= t_begin.
  // With a finite max_winding_rad (>= pi) the scanner never turns further than that
  // either way from its heading at t_begin, as a wrist joint can turn only so far: where
  // following would wind it further, it turns back the other way round, a whole turn
  // less, at the limit rate (an unwind). `unwind_early(t)`, when given, says where an
  // unwind costs least (moves that lay no bead): there the scanner unwinds as soon as it
  // has wound more than half a turn, so that it seldom reaches the limit while printing.
  // An unwind, once begun, keeps its way round until it has caught up.
  TurnRateLimit(const std::function<double(double)>& followed, double t_begin, double t_end, double max_rate_rad_s,
                double max_winding_rad = std::numeric_limits<double>::infinity(),
                const std::function<bool(double)>& unwind_early = {}, double step_s = 1e-3);

  // The limited heading at t (clamped to [t_begin, t_end]), and whether t lies on a
  // slew. On a following piece this is followed(t) itself.
  double HeadingAt(double t_s, const std::function<double(double)>& followed) const;
  bool SlewingAt(double t_s) const;

  // Largest turn rate: the limit where any slew occurs, else the followed heading's
  // largest over a step (and when).
  double max_rate_rad_s() const { return max_rate_rad_s_seen_; }
  double max_rate_time_s() const { return max_rate_time_s_; }
  // Number of slews and the longest one (s), and the time it starts.
  size_t slews() const { return slews_; }
  double longest_slew_s() const { return longest_slew_s_; }
  double longest_slew_start_s() const { return longest_slew_start_s_; }
  // Slews made to unwind, and the farthest the scanner turns from its start (rad).
  size_t unwinds() const { return unwinds_; }
  double max_winding_rad() const { return max_winding_seen_rad_; }

 private:
  struct Piece {
    double t0;
    double angle0;  // slewing: the heading at t0
    int dir;        // 0 following, +-1 slewing counter-clockwise / clockwise
  };
  size_t PieceAt(double t_s) const;

  double t_begin_, t_end_, rate_;
  std::vector<Piece> pieces_;
  double max_rate_rad_s_seen_ = 0, max_rate_time_s_ = 0;
  size_t slews_ = 0;
  double longest_slew_s_ = 0, longest_slew_start_s_ = 0;
  size_t unwinds_ = 0;
  double max_winding_seen_rad_ = 0;
};

}  // namespace lt

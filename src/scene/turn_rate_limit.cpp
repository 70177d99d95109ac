#include "scene/turn_rate_limit.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace lt {

namespace {

// Steps of at most this many over the whole span (the step grows past it).
constexpr double kMaxSteps = 2e7;
constexpr double kBisectionS = 1e-9;

// The angle a, in (-pi, pi].
double Wrap(double a) { return std::remainder(a, 2 * M_PI); }

}  // namespace

TurnRateLimit::TurnRateLimit(const std::function<double(double)>& followed, double t_begin, double t_end,
                             double max_rate_rad_s, double max_winding_rad,
                             const std::function<bool(double)>& unwind_early, double step_s)
    : t_begin_(t_begin), t_end_(t_end), rate_(max_rate_rad_s) {
  if (!(std::isfinite(max_rate_rad_s) && max_rate_rad_s > 0)) throw std::invalid_argument("turn rate limit must be > 0");
  if (!(max_winding_rad >= M_PI)) throw std::invalid_argument("winding limit must be >= 180 degrees");
  if (!(std::isfinite(step_s) && step_s > 0)) throw std::invalid_argument("turn rate step must be > 0");
  if (!(std::isfinite(t_begin) && std::isfinite(t_end) && t_end >= t_begin)) {
    throw std::invalid_argument("turn rate limit: empty time span");
  }
  const double dt = std::max(step_s, (t_end - t_begin) / kMaxSteps);
  pieces_.push_back({t_begin, 0.0, 0});
  auto slew_ends = [&](const Piece& slew, double t) {
    if (t - slew.t0 > longest_slew_s_) {
      longest_slew_s_ = t - slew.t0;
      longest_slew_start_s_ = slew.t0;
    }
  };
  // `heading` is unwound (continuous): how far the scanner has turned from where it
  // started is heading - start, which the winding limit bounds.
  const double start = followed(t_begin);
  double heading = start;
  // While an unwind is under way: the turns (a multiple of 2 pi) it adds to the
  // followed heading, kept until it has caught up.
  std::optional<double> unwind_turns;
  for (double t = t_begin; t < t_end;) {
    const double t_next = std::min(t + dt, t_end), h = t_next - t;
    const double f = followed(t_next);
    // The followed heading's nearest turn, or the next one the other way round where
    // the nearest would wind the scanner past the limit (or past half a turn where
    // unwinding costs least).
    double target = unwind_turns ? f + *unwind_turns : heading + Wrap(f - heading);
    const double wound = std::abs(target - start);
    const bool unwinding = wound > max_winding_rad || (!unwind_turns && std::isfinite(max_winding_rad) &&
                                                         unwind_early && wound > M_PI && unwind_early(t_next));
    if (unwinding) target -= std::copysign(2 * M_PI, target - start);
    const double need = target - heading;
    const double turns = 2 * M_PI * std::round((target - f) / (2 * M_PI));  // target = followed + turns
    Piece& cur = pieces_.back();
    if (std::abs(need) <= rate_ * h) {
      if (cur.dir != 0) {
        // The slew meets the followed heading within this step: where, by bisection on
        // how far it still has to go (positive at t, not at t_next).
        const Piece slew = cur;
        auto left = [&](double tau) {
          // Wrapped: within the step the gap is small, and the followed heading may cross +-pi.
          return slew.dir * Wrap(followed(tau) + turns - (slew.angle0 + slew.dir * rate_ * (tau - slew.t0)));
        };
        double a = t, b = t_next;
        while (b - a > kBisectionS) {
          const double m = 0.5 * (a + b);
          (left(m) > 0 ? a : b) = m;
        }
        pieces_.push_back({b, 0.0, 0});
        slew_ends(slew, b);
        unwind_turns.reset();
      } else if (std::abs(need) / h > max_rate_rad_s_seen_ && slews_ == 0) {
        max_rate_rad_s_seen_ = std::abs(need) / h;
        max_rate_time_s_ = t;
      }
      heading = target;
    } else {
      const int dir = need > 0 ? 1 : -1;
      if (cur.dir != dir) {
        if (cur.dir != 0) slew_ends(cur, t);  // a slew that turns round: it ends here
        if (pieces_.back().t0 == t) pieces_.pop_back();
        pieces_.push_back({t, heading, dir});
        unwind_turns.reset();
        if (unwinding) {
          ++unwinds_;
          unwind_turns = turns;
        }
        if (slews_++ == 0) {
          max_rate_rad_s_seen_ = rate_;
          max_rate_time_s_ = t;
        }
      }
      heading += dir * rate_ * h;
    }
    max_winding_seen_rad_ = std::max(max_winding_seen_rad_, std::abs(heading - start));
    t = t_next;
  }
  if (pieces_.back().dir != 0) slew_ends(pieces_.back(), t_end);
}

size_t TurnRateLimit::PieceAt(double t_s) const {
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t_s, [](double t, const Piece& p) { return t < p.t0; });
  return it == pieces_.begin() ? 0 : size_t(it - pieces_.begin()) - 1;
}

double TurnRateLimit::HeadingAt(double t_s, const std::function<double(double)>& followed) const {
  const double t = std::clamp(t_s, t_begin_, t_end_);
  const Piece& p = pieces_[PieceAt(t)];
  if (p.dir == 0) return followed(t);
  return Wrap(p.angle0 + p.dir * rate_ * (t - p.t0));
}

bool TurnRateLimit::SlewingAt(double t_s) const {
  return pieces_[PieceAt(std::clamp(t_s, t_begin_, t_end_))].dir != 0;
}

}  // namespace lt

#include "scene/turn_rate_limit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lt {

namespace {

// Steps of at most this many over the whole span (the step grows past it).
constexpr double kMaxSteps = 2e7;
constexpr double kBisectionS = 1e-9;

// The angle a minus b, in (-pi, pi].
double Wrap(double a) { return std::remainder(a, 2 * M_PI); }

}  // namespace

TurnRateLimit::TurnRateLimit(const std::function<double(double)>& followed, double t_begin, double t_end,
                             double max_rate_rad_s, double step_s)
    : t_begin_(t_begin), t_end_(t_end), rate_(max_rate_rad_s) {
  if (!(std::isfinite(max_rate_rad_s) && max_rate_rad_s > 0)) throw std::invalid_argument("turn rate limit must be > 0");
  if (!(std::isfinite(step_s) && step_s > 0)) throw std::invalid_argument("turn rate step must be > 0");
  if (!(std::isfinite(t_begin) && std::isfinite(t_end) && t_end >= t_begin)) {
    throw std::invalid_argument("turn rate limit: empty time span");
  }
  const double dt = std::max(step_s, (t_end - t_begin) / kMaxSteps);
  pieces_.push_back({t_begin, 0.0, 0});
  double heading = followed(t_begin);
  for (double t = t_begin; t < t_end;) {
    const double t_next = std::min(t + dt, t_end), h = t_next - t;
    const double need = Wrap(followed(t_next) - heading);
    Piece& cur = pieces_.back();
    if (std::abs(need) <= rate_ * h) {
      if (cur.dir != 0) {
        // The slew meets the followed heading within this step: where, by bisection on
        // how far it still has to go (positive at t, not at t_next).
        const Piece slew = cur;
        auto left = [&](double tau) { return slew.dir * Wrap(followed(tau) - (slew.angle0 + slew.dir * rate_ * (tau - slew.t0))); };
        double a = t, b = t_next;
        while (b - a > kBisectionS) {
          const double m = 0.5 * (a + b);
          (left(m) > 0 ? a : b) = m;
        }
        pieces_.push_back({b, 0.0, 0});
        const double length = b - slew.t0;
        if (length > longest_slew_s_) {
          longest_slew_s_ = length;
          longest_slew_start_s_ = slew.t0;
        }
      } else if (std::abs(need) / h > max_rate_rad_s_seen_ && slews_ == 0) {
        max_rate_rad_s_seen_ = std::abs(need) / h;
        max_rate_time_s_ = t;
      }
      heading += need;
    } else {
      const int dir = need > 0 ? 1 : -1;
      if (cur.dir != dir) {
        if (cur.dir != 0) {  // a slew that turns round: it ends here
          const double length = t - cur.t0;
          if (length > longest_slew_s_) {
            longest_slew_s_ = length;
            longest_slew_start_s_ = cur.t0;
          }
        }
        if (pieces_.back().t0 == t) pieces_.pop_back();
        pieces_.push_back({t, heading, dir});
        if (slews_++ == 0) {
          max_rate_rad_s_seen_ = rate_;
          max_rate_time_s_ = t;
        }
      }
      heading += dir * rate_ * h;
    }
    t = t_next;
  }
  if (pieces_.back().dir != 0 && t_end - pieces_.back().t0 > longest_slew_s_) {
    longest_slew_s_ = t_end - pieces_.back().t0;
    longest_slew_start_s_ = pieces_.back().t0;
  }
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

#include "scene/caster.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lt {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kJumpThresholdRad = 1e-9;
constexpr int kArcSamples = 17;

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double AngleBetween(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::abs(std::atan2(Cross(a, b), a.dot(b)));
}

}  // namespace

void OrientationOptions::Check() const {
  if (!(std::isfinite(caster_window_m) && caster_window_m > 0)) {
    throw std::invalid_argument("caster window must be > 0");
  }
  if (!(std::isfinite(trail_m) && trail_m > 0)) throw std::invalid_argument("trail must be > 0");
  if (!(std::isfinite(max_turn_rad_s) && max_turn_rad_s >= 0)) {
    throw std::invalid_argument("turn rate limit must be >= 0");
  }
  if (!(max_winding_rad >= M_PI)) throw std::invalid_argument("winding limit must be >= 180 degrees");
  if (std::isfinite(max_winding_rad) && max_turn_rad_s == 0) {
    throw std::invalid_argument("a winding limit needs a turn rate limit to unwind at");
  }
}

std::string OrientationModeName(OrientationMode mode) {
  switch (mode) {
    case OrientationMode::kFixed: return "fixed";
    case OrientationMode::kHeading: return "heading";
    case OrientationMode::kCaster: return "caster";
    case OrientationMode::kTrailing: return "trailing";
  }
  return "caster";
}

OrientationMode ParseOrientationMode(const std::string& name) {
  if (name == "fixed") return OrientationMode::kFixed;
  if (name == "heading") return OrientationMode::kHeading;
  if (name == "caster") return OrientationMode::kCaster;
  if (name == "trailing") return OrientationMode::kTrailing;
  throw std::invalid_argument("unknown orientation mode \"" + name + "\"");
}

double TurnRates::MaxRateDegS() const { return max_rate_rad_s * kRadToDeg; }
double TurnRates::MaxJumpDeg() const { return max_jump_rad * kRadToDeg; }

ToolpathOrientation::ToolpathOrientation(std::shared_ptr<const Toolpath> path, OrientationOptions options)
    : path_(std::move(path)), options_(options) {
  options_.Check();
  const auto& segs = path_->segments;
  s_start_m_.resize(segs.size());
  double s = 0;
  for (size_t i = 0; i < segs.size(); ++i) {
    s_start_m_[i] = s;
    if (segs[i].xy_length_m > 0) {
      xy_segments_.push_back(i);
      s += segs[i].xy_length_m;
    }
  }
  total_xy_m_ = s;
  if (options_.mode == OrientationMode::kTrailing) StartTrailingWheel();
  if (options_.max_turn_rad_s > 0 && !segs.empty()) {
    limit_.emplace([this](double t) { return RuleHeadingAt(t); }, segs.front().t_start_s, segs.back().t_end_s,
                   options_.max_turn_rad_s, options_.max_winding_rad,
                   [this](double t) { return !path_->segments[path_->SegmentIndexAt(t)].LaysBead(); });
  }
}

size_t ToolpathOrientation::SegmentAtLength(double s_m) const {
  // The last segment with motion in the plane that starts at or before s.
  auto it = std::upper_bound(xy_segments_.begin(), xy_segments_.end(), s_m,
                             [this](double s, size_t i) { return s < s_start_m_[i]; });
  if (it == xy_segments_.begin()) return xy_segments_.front();
  return *(it - 1);
}

double ToolpathOrientation::PathLengthAt(double t_s) const {
  if (path_->segments.empty()) return 0;
  size_t k = path_->SegmentIndexAt(t_s);
  const ToolpathSegment& seg = path_->segments[k];
  double d = seg.Duration();
  double u = d > 0 ? std::clamp((t_s - seg.t_start_s) / d, 0.0, 1.0) : 1.0;
  if (!(t_s > seg.t_start_s)) u = 0;  // also NaN
  return s_start_m_[k] + u * seg.xy_length_m;
}

Eigen::Vector2d ToolpathOrientation::PointAtLength(double s_m) const {
  if (xy_segments_.empty()) {
    return path_->segments.empty() ? Eigen::Vector2d::Zero() : Eigen::Vector2d(path_->segments.front().start_m.head<2>());
  }
  size_t k = SegmentAtLength(s_m);
  const ToolpathSegment& seg = path_->segments[k];
  double u = std::clamp((s_m - s_start_m_[k]) / seg.xy_length_m, 0.0, 1.0);
  return seg.PointAt(u).head<2>();
}

Eigen::Vector2d ToolpathOrientation::MoveDirectionAt(double t_s) const {
  if (xy_segments_.empty()) return Eigen::Vector2d::UnitX();
  size_t k = path_->SegmentIndexAt(t_s);
  const ToolpathSegment& seg = path_->segments[k];
  if (seg.xy_length_m > 0) {
    double d = seg.Duration();
    double u = std::clamp((t_s - seg.t_start_s) / d, 0.0, 1.0);
    if (!(t_s > seg.t_start_s)) u = 0;
    return seg.TangentXy(u);
  }
  // No motion in the plane: the last move that had some, else the first to come.
  auto it = std::upper_bound(xy_segments_.begin(), xy_segments_.end(), k);
  if (it == xy_segments_.begin()) return path_->segments[xy_segments_.front()].TangentXy(0);
  return path_->segments[*(it - 1)].TangentXy(1);
}

Eigen::Vector2d ToolpathOrientation::CasterDirectionAt(double s_m, size_t segment) const {
  double tail = std::max(0.0, s_m - options_.caster_window_m);
  Eigen::Vector2d chord = PointAtLength(s_m) - PointAtLength(tail);
  double n = chord.norm();
  if (n > 1e-12) return chord / n;
  // No chord yet (at the very start): the direction of the move.
  const ToolpathSegment& seg = path_->segments[segment];
  double u = std::clamp((s_m - s_start_m_[segment]) / seg.xy_length_m, 0.0, 1.0);
  return seg.TangentXy(u);
}

Eigen::Vector2d ToolpathOrientation::DirectionAt(double t_s) const {
  if (!limit_) return RuleDirectionAt(t_s);
  const double heading = limit_->HeadingAt(t_s, [this](double t) { return RuleHeadingAt(t); });
  return {std::cos(heading), std::sin(heading)};
}

double ToolpathOrientation::RuleHeadingAt(double t_s) const {
  const Eigen::Vector2d d = RuleDirectionAt(t_s);
  return std::atan2(d.y(), d.x());
}

Eigen::Vector2d ToolpathOrientation::RuleDirectionAt(double t_s) const {
  switch (options_.mode) {
    case OrientationMode::kFixed: return Eigen::Vector2d::UnitX();
    case OrientationMode::kHeading: return MoveDirectionAt(t_s);
    case OrientationMode::kCaster: {
      if (xy_segments_.empty()) return Eigen::Vector2d::UnitX();
      double s = PathLengthAt(t_s);
      return CasterDirectionAt(s, SegmentAtLength(s));
    }
    case OrientationMode::kTrailing: {
      if (xy_segments_.empty()) return Eigen::Vector2d::UnitX();
      double s = PathLengthAt(t_s);
      return TrailingDirectionAt(s, SegmentAtLength(s));
    }
  }
  return Eigen::Vector2d::UnitX();
}

double ToolpathOrientation::HeadingAt(double t_s) const {
  Eigen::Vector2d d = DirectionAt(t_s);
  return std::atan2(d.y(), d.x());
}

TurnRates ToolpathOrientation::ComputeTurnRates() const {
  if (limit_) {
    TurnRates r;
    r.max_rate_rad_s = limit_->max_rate_rad_s();
    r.max_rate_time_s = limit_->max_rate_time_s();
    r.slews = limit_->slews();
    r.longest_slew_s = limit_->longest_slew_s();
    r.longest_slew_time_s = limit_->longest_slew_start_s();
    r.unwinds = limit_->unwinds();
    r.max_winding_rad = limit_->max_winding_rad();
    return r;
  }
  switch (options_.mode) {
    case OrientationMode::kFixed: return TurnRates{};
    case OrientationMode::kHeading: return HeadingTurnRates();
    case OrientationMode::kCaster: return CasterTurnRates();
    case OrientationMode::kTrailing: return TrailingTurnRates();
  }
  return TurnRates{};
}

TurnRates ToolpathOrientation::HeadingTurnRates() const {
  TurnRates r;
  const auto& segs = path_->segments;
  for (size_t n = 0; n < xy_segments_.size(); ++n) {
    const ToolpathSegment& seg = segs[xy_segments_[n]];
    if (seg.arc) {
      // The tangent turns with the radius vector: |sweep| over the move's duration.
      double rate = std::abs(seg.sweep_rad) / seg.Duration();
      if (rate > r.max_rate_rad_s) {
        r.max_rate_rad_s = rate;
        r.max_rate_time_s = 0.5 * (seg.t_start_s + seg.t_end_s);
      }
    }
    if (n > 0) {
      double jump = AngleBetween(segs[xy_segments_[n - 1]].TangentXy(1), seg.TangentXy(0));
      if (jump > kJumpThresholdRad) {
        ++r.jumps;
        if (jump > r.max_jump_rad) {
          r.max_jump_rad = jump;
          r.max_jump_time_s = seg.t_start_s;
          r.max_jump_line = seg.line;
        }
      }
    }
  }
  return r;
}

TurnRates ToolpathOrientation::CasterTurnRates() const {
  TurnRates r;
  if (xy_segments_.empty()) return r;
  const auto& segs = path_->segments;
  const double w = options_.caster_window_m;
  // Pieces of head path length over which the nozzle and the window's tail each stay
  // on one move: bounded by the moves' ends, and the same shifted by w.
  std::vector<double> cuts;
  cuts.reserve(4 * xy_segments_.size() + 2);
  for (size_t i : xy_segments_) {
    for (double s : {s_start_m_[i], s_start_m_[i] + segs[i].xy_length_m}) {
      cuts.push_back(s);
      if (s + w < total_xy_m_) cuts.push_back(s + w);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());

  auto point_on = [&](size_t k, double s) {
    double u = std::clamp((s - s_start_m_[k]) / segs[k].xy_length_m, 0.0, 1.0);
    return Eigen::Vector2d(segs[k].PointAt(u).head<2>());
  };
  auto tangent_on = [&](size_t k, double s) {
    double u = std::clamp((s - s_start_m_[k]) / segs[k].xy_length_m, 0.0, 1.0);
    return segs[k].TangentXy(u);
  };
  for (size_t p = 0; p + 1 < cuts.size(); ++p) {
    const double a = cuts[p], b = cuts[p + 1];
    if (!(b - a > 1e-15)) continue;
    const double mid = 0.5 * (a + b);
    const size_t head = SegmentAtLength(mid);
    const bool tail_fixed = mid - w < 0;  // the window still reaches back to the start
    const size_t tail = tail_fixed ? xy_segments_.front() : SegmentAtLength(mid - w);
    const Eigen::Vector2d start = point_on(xy_segments_.front(), 0.0);
    const double speed = segs[head].xy_length_m / segs[head].Duration();
    // d heading / ds = chord x (d chord / ds) / |chord|^2, d chord / ds = T(head) - T(tail).
    auto rate_at = [&](double s) {
      Eigen::Vector2d chord = point_on(head, s) - (tail_fixed ? start : point_on(tail, s - w));
      Eigen::Vector2d dchord = tangent_on(head, s) - (tail_fixed ? Eigen::Vector2d::Zero() : tangent_on(tail, s - w));
      double c2 = std::max(chord.squaredNorm(), 1e-24);
      return std::abs(Cross(chord, dchord)) / c2 * speed;
    };
    auto consider = [&](double s) {
      double rate = rate_at(s);
      if (rate > r.max_rate_rad_s) {
        r.max_rate_rad_s = rate;
        const ToolpathSegment& h = segs[head];
        r.max_rate_time_s = h.t_start_s + std::clamp((s - s_start_m_[head]) / h.xy_length_m, 0.0, 1.0) * h.Duration();
      }
    };
    const bool straight = !segs[head].arc && (tail_fixed || !segs[tail].arc);
    if (straight) {
      // The chord moves linearly with s; the rate peaks where it is shortest.
      Eigen::Vector2d ca = point_on(head, a) - (tail_fixed ? start : point_on(tail, a - w));
      Eigen::Vector2d d = tangent_on(head, mid) - (tail_fixed ? Eigen::Vector2d::Zero() : tangent_on(tail, mid - w));
      double dd = d.squaredNorm();
      double s_star = dd > 0 ? std::clamp(a - ca.dot(d) / dd, a, b) : a;
      consider(a);
      consider(b);
      consider(s_star);
      // A chord shrinking through zero along its own line (the path doubling back
      // exactly on itself) turns the heading by 180 degrees at once.
      const Eigen::Vector2d c_star = ca + (s_star - a) * d;
      if (s_star > a && s_star < b && c_star.norm() <= 1e-9 * w && std::abs(Cross(ca, d)) <= 1e-9 * w * std::sqrt(dd)) {
        ++r.jumps;
        if (M_PI > r.max_jump_rad) {
          const ToolpathSegment& h = segs[head];
          r.max_jump_rad = M_PI;
          r.max_jump_time_s = h.t_start_s + std::clamp((s_star - s_start_m_[head]) / h.xy_length_m, 0.0, 1.0) * h.Duration();
          r.max_jump_line = h.line;
        }
      }
    } else {
      for (int k = 0; k < kArcSamples; ++k) consider(a + (b - a) * k / (kArcSamples - 1));
    }
  }
  return r;
}

}  // namespace lt

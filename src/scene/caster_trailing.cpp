// The trailing-wheel rule of ToolpathOrientation (scene/caster.h): the wheel's state
// at the start of each move, its heading along a move, and its turn rates.
#include <algorithm>
#include <cmath>

#include "scene/caster.h"
#include "scene/trailing_wheel.h"

namespace lt {

namespace {

// A reversal leaves the wheel within this of pointing straight back: taken as this off.
constexpr double kReversalOffsetRad = M_PI / 180;
// On arcs the turn rate is sampled where the angle off the path turns by at most this.
constexpr double kArcStepRad = 0.05;
constexpr int kMaxArcSteps = 1 << 16;

double AngleOf(const Eigen::Vector2d& d) { return std::atan2(d.y(), d.x()); }

}  // namespace

double ToolpathOrientation::CurvatureOf(size_t segment) const {
  const ToolpathSegment& seg = path_->segments[segment];
  return seg.arc ? seg.sweep_rad / seg.xy_length_m : 0.0;
}

double ToolpathOrientation::TrailingAngleOffPath(double s_m, size_t segment) const {
  const double along = std::clamp(s_m - s_start_m_[segment], 0.0, path_->segments[segment].xy_length_m);
  return WheelAngle(TrailAlong(wheel_start_[segment], along, options_.trail_m, CurvatureOf(segment)));
}

Eigen::Vector2d ToolpathOrientation::TrailingDirectionAt(double s_m, size_t segment) const {
  const ToolpathSegment& seg = path_->segments[segment];
  const double u = std::clamp((s_m - s_start_m_[segment]) / seg.xy_length_m, 0.0, 1.0);
  const double heading = AngleOf(seg.TangentXy(u)) + TrailingAngleOffPath(s_m, segment);
  return {std::cos(heading), std::sin(heading)};
}

void ToolpathOrientation::StartTrailingWheel() {
  const auto& segs = path_->segments;
  wheel_start_.assign(segs.size(), WheelHalfAngle(0));  // the first move starts the wheel in line
  wheel_jump_rad_.assign(segs.size(), 0.0);
  for (size_t n = 1; n < xy_segments_.size(); ++n) {
    const size_t prev = xy_segments_[n - 1], k = xy_segments_[n];
    const double end = s_start_m_[prev] + segs[prev].xy_length_m;
    const double heading = AngleOf(segs[prev].TangentXy(1)) + TrailingAngleOffPath(end, prev);
    const double psi = std::remainder(heading - AngleOf(segs[k].TangentXy(0)), 2 * M_PI);
    const double kept = std::clamp(psi, -(M_PI - kReversalOffsetRad), M_PI - kReversalOffsetRad);
    wheel_start_[k] = WheelHalfAngle(kept);
    wheel_jump_rad_[k] = std::abs(psi - kept);
  }
}

TurnRates ToolpathOrientation::TrailingTurnRates() const {
  TurnRates r;
  const auto& segs = path_->segments;
  const double w = options_.trail_m;
  // The heading turns at v |sin psi| / w (psi the angle off the path).
  auto consider = [&](const ToolpathSegment& seg, double sin_psi, double along_m) {
    const double rate = std::abs(sin_psi) * seg.xy_length_m / seg.Duration() / w;
    if (rate > r.max_rate_rad_s) {
      r.max_rate_rad_s = rate;
      r.max_rate_time_s = seg.t_start_s + std::clamp(along_m / seg.xy_length_m, 0.0, 1.0) * seg.Duration();
    }
  };
  for (size_t n = 0; n < xy_segments_.size(); ++n) {
    const size_t k = xy_segments_[n];
    const ToolpathSegment& seg = segs[k];
    const double length = seg.xy_length_m;
    // The reversal offset is the one jump of the heading.
    if (wheel_jump_rad_[k] > 0) {
      ++r.jumps;
      if (wheel_jump_rad_[k] > r.max_jump_rad) {
        r.max_jump_rad = wheel_jump_rad_[k];
        r.max_jump_time_s = seg.t_start_s;
        r.max_jump_line = seg.line;
      }
    }
    const double kappa = CurvatureOf(k);
    if (kappa == 0) {
      // |psi| shrinks monotonically towards 0: |tan(psi/2)| = |tan(psi0/2)| exp(-s/w).
      const double psi0 = WheelAngle(wheel_start_[k]);
      const double psi1 = TrailingAngleOffPath(s_start_m_[k] + length, k);
      if (std::abs(psi0) >= M_PI / 2 && std::abs(psi1) <= M_PI / 2) {
        consider(seg, 1.0, w * std::log(std::abs(std::tan(0.5 * psi0))));
      } else {
        consider(seg, std::sin(psi0), 0);
        consider(seg, std::sin(psi1), length);
      }
      continue;
    }
    // On an arc psi moves monotonically (an autonomous equation in one angle), by at
    // most (1/w + |kappa|) per metre: step so that it turns kArcStepRad at most, and
    // take a crossing of +-pi/2 (unwrapped) as the rate's peak.
    const int steps = int(std::clamp(std::ceil((1 / w + std::abs(kappa)) * length / kArcStepRad), 1.0,
                                     double(kMaxArcSteps)));
    const double ds = length / steps;
    Eigen::Vector2d half = wheel_start_[k];
    double psi = WheelAngle(half);
    consider(seg, std::sin(psi), 0);
    for (int i = 1; i <= steps; ++i) {
      half = TrailAlong(half, ds, w, kappa);
      const double next = psi + std::remainder(WheelAngle(half) - psi, 2 * M_PI);
      if (std::floor((psi - M_PI / 2) / M_PI) != std::floor((next - M_PI / 2) / M_PI)) {
        consider(seg, 1.0, (i - 0.5) * ds);
      }
      consider(seg, std::sin(next), i * ds);
      psi = next;
    }
  }
  return r;
}

}  // namespace lt

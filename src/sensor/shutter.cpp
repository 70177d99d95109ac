#include "sensor/shutter.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "sensor/param_error.h"

namespace lt {

namespace {
constexpr double kJitterClamp = 5.0;
}

ShutterParams AlternatingShutter(double bright_exposure_s, double dim_exposure_s, double frame_period_s,
                                 bool led_in_bright) {
  ShutterParams p;
  p.cycle = {ShutterFrameSpec{"bright", bright_exposure_s, false, false, led_in_bright, std::nullopt},
             ShutterFrameSpec{"dim", dim_exposure_s, true, false, false, std::nullopt}};
  p.frame_period_s = frame_period_s;
  return p;
}

void ShutterParams::Check() const {
  if (cycle.empty()) throw ParamError("cycle", "must have at least one frame");
  for (size_t c = 0; c < cycle.size(); ++c) {
    if (!(cycle[c].exposure_s > 0 && std::isfinite(cycle[c].exposure_s))) {
      throw ParamError("cycle/" + std::to_string(c) + "/exposure_us", "must be > 0");
    }
    if (cycle[c].analog_gain_db && !(std::abs(*cycle[c].analog_gain_db) <= 60)) {
      throw ParamError("cycle/" + std::to_string(c) + "/analog_gain_db", "must be in [-40, 60]");
    }
  }
  if (!(frame_period_s > 0 && std::isfinite(frame_period_s))) throw ParamError("frame_period_ms", "must be > 0");
  if (!(exposure_change_overhead_s >= 0 && std::isfinite(exposure_change_overhead_s))) {
    throw ParamError("exposure_change_overhead_ms", "must be >= 0");
  }
  if (!std::isfinite(sync_offset_s)) throw ParamError("sync_offset_us", "must be finite");
  if (!(sync_jitter_s >= 0 && std::isfinite(sync_jitter_s))) throw ParamError("sync_jitter_us", "must be >= 0");
  if (!std::isfinite(start_time_s)) throw ParamError("start_time_s", "must be finite");
  // Switching events must stay in frame order: |offset| + 5σ below half the shortest gap.
  // (Every gap is at least the frame period.)
  const double min_gap = frame_period_s;
  if (!(std::abs(sync_offset_s) + kJitterClamp * sync_jitter_s < 0.5 * min_gap)) {
    throw ParamError("sync_offset_us", "|sync_offset| + 5·sync_jitter must be below half the frame period (" +
                                           FormatNumber(0.5 * min_gap * 1e6) + " us)");
  }
}

ShutterSchedule::ShutterSchedule(const ShutterParams& params) : params_(params) {
  params_.Check();
  size_t n = params_.cycle.size();
  gap_.resize(n);
  offset_.resize(n);
  double t = 0;
  for (size_t c = 0; c < n; ++c) {
    const auto& cur = params_.cycle[c];
    const auto& next = params_.cycle[(c + 1) % n];
    gap_[c] = std::max(params_.frame_period_s, cur.exposure_s) +
              (next.exposure_s != cur.exposure_s ? params_.exposure_change_overhead_s : 0.0);
    offset_[c] = t;
    t += gap_[c];
  }
  cycle_duration_ = t;
}

double ShutterSchedule::FrameStart(int64_t index) const {
  int64_t n = int64_t(params_.cycle.size());
  int64_t cycles = index >= 0 ? index / n : -((-index + n - 1) / n);
  int64_t c = index - cycles * n;
  return params_.start_time_s + double(cycles) * cycle_duration_ + offset_[size_t(c)];
}

double ShutterSchedule::SwitchTime(int64_t index, uint64_t seed) const {
  double jitter = 0;
  if (params_.sync_jitter_s > 0) {
    Rng rng = Rng::For(seed, uint64_t(index), 0, 0, kShutterPurpose);
    jitter = params_.sync_jitter_s * std::clamp(rng.NextGaussian(), -kJitterClamp, kJitterClamp);
  }
  return FrameStart(index) + params_.sync_offset_s + jitter;
}

// Time during frame `index`'s exposure that light (0 laser, 1 pattern, 2 led) is
// lit. Times are taken relative to the frame's start so that perfect
// synchronisation gives exactly 0 or the full exposure.
double ShutterSchedule::LitTime(int light, int64_t index, double exposure, uint64_t seed) const {
  const double t0 = FrameStart(index);
  auto switch_rel = [&](int64_t j) { return (FrameStart(j) - t0) + (SwitchTime(j, seed) - FrameStart(j)); };
  double lit = 0;
  int64_t n = int64_t(params_.cycle.size());
  for (int64_t j = std::max<int64_t>(0, index - 2); j <= index + 1; ++j) {
    const auto& spec = params_.cycle[size_t(j % n)];
    bool on = light == 0 ? spec.laser : light == 1 ? spec.pattern : spec.led;
    if (!on) continue;
    double s0 = j == index ? SwitchTime(j, seed) - t0 : switch_rel(j);
    double s1 = switch_rel(j + 1);
    lit += std::max(0.0, std::min(exposure, s1) - std::max(0.0, s0));
  }
  return std::min(lit, exposure);
}

ShutterFrame ShutterSchedule::Frame(int64_t index, uint64_t seed) const {
  if (index < 0) throw std::out_of_range("shutter frame index must be >= 0");
  int64_t n = int64_t(params_.cycle.size());
  ShutterFrame f;
  f.index = index;
  f.cycle_index = int(index % n);
  const auto& spec = params_.cycle[size_t(f.cycle_index)];
  f.label = spec.label;
  f.exposure_s = spec.exposure_s;
  f.t_start_s = FrameStart(index);
  f.t_end_s = f.t_start_s + spec.exposure_s;
  f.laser_on = spec.laser;
  f.pattern_on = spec.pattern;
  f.led_on = spec.led;
  f.analog_gain_db = spec.analog_gain_db;
  f.switch_time_s = SwitchTime(index, seed);
  f.laser_fraction = LitTime(0, index, spec.exposure_s, seed) / spec.exposure_s;
  f.pattern_fraction = LitTime(1, index, spec.exposure_s, seed) / spec.exposure_s;
  f.led_fraction = LitTime(2, index, spec.exposure_s, seed) / spec.exposure_s;
  return f;
}

std::vector<ShutterFrame> ShutterSchedule::Frames(int64_t count, uint64_t seed) const {
  std::vector<ShutterFrame> out;
  out.reserve(size_t(std::max<int64_t>(0, count)));
  for (int64_t i = 0; i < count; ++i) out.push_back(Frame(i, seed));
  return out;
}

}  // namespace lt

// The shutter schedule: a repeating cycle of frames (exposure, which lights are
// on), the camera's frame period, the overhead of changing the exposure, and
// the synchronisation error between light switching and exposure.
//
// Timing model. Frame i uses cycle entry c = i mod L. It starts at
//   t_start(0) = start_time,  t_start(i+1) = t_start(i) + max(frame_period, exposure_c)
//                                          + (exposure_{c+1} ≠ exposure_c ? exposure_change_overhead : 0)
// and exposes [t_start, t_start + exposure]. The lights (lasers, pattern projector,
// LED) are switched to frame i's commanded state at
//   s_i = t_start(i) + sync_offset + jitter_i,   jitter_i ~ σ_jitter·N(0,1) clamped to ±5σ
// (one switching event per frame for all lights; Rng::For(seed, i, 0, 0,
// kShutterPurpose)); before s_0 every light is off. A light is lit during
// [s_j, s_{j+1}) when frame j commands it on. Each frame records, per light,
// the fraction of its exposure during which the light was lit: 1 for a light
// commanded on with perfect sync, > 0 for a light commanded off that is still lit
// at the start of the exposure (sync_offset > 0: lights switch late) — the laser
// "bleeding" into bright frames.
//
// The thesis camera (XIMEA MU181CR-ON, 1000x700) ran at 51.7 bright fps with a
// constant exposure (a bright/dim pair every 19.3 ms) and at 29.7 bright fps
// when the exposure was toggled (33.6 ms per pair): 14.3 ms more per pair, that
// is 7.15 ms per exposure change in this model, where an alternating cycle
// changes the exposure twice per pair.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lt {

constexpr uint64_t kShutterPurpose = 0x5348555454455231ull;

struct ShutterFrameSpec {
  std::string label = "frame";  // e.g. "bright", "dim"
  double exposure_s = 1e-3;
  bool laser = true;    // all laser projectors
  bool pattern = false;  // the pattern projector
  bool led = false;     // the LED flood light
  std::optional<double> analog_gain_db = std::nullopt;  // overrides the image sensor's gain in this frame
};

struct ShutterParams {
  std::vector<ShutterFrameSpec> cycle = {ShutterFrameSpec{}};
  double frame_period_s = 1.0 / 60.0;
  double exposure_change_overhead_s = 0.0;
  double sync_offset_s = 0.0;  // switching time − exposure start
  double sync_jitter_s = 0.0;  // σ of the switching time
  double start_time_s = 0.0;

  // Throws ParamError naming the key.
  void Check() const;
};

// The alternating schedule of the thesis: a bright frame (LED on, lasers off)
// then a dim frame (lasers on, LED off).
ShutterParams AlternatingShutter(double bright_exposure_s, double dim_exposure_s, double frame_period_s,
                                 bool led_in_bright = true);

struct ShutterFrame {
  int64_t index = 0;
  int cycle_index = 0;
  std::string label;
  double t_start_s = 0, t_end_s = 0, exposure_s = 0;
  bool laser_on = false, pattern_on = false, led_on = false;  // commanded for this frame
  std::optional<double> analog_gain_db;  // this frame's gain when the cycle sets one
  double switch_time_s = 0;  // when the lights were switched to this frame's state
  // Fraction of [t_start, t_end] during which each light was lit (0..1). The
  // renderer multiplies each light's irradiance by exposure_s · fraction.
  double laser_fraction = 0, pattern_fraction = 0, led_fraction = 0;
  double laser_on_time_s() const { return laser_fraction * exposure_s; }
  double pattern_on_time_s() const { return pattern_fraction * exposure_s; }
  double led_on_time_s() const { return led_fraction * exposure_s; }
};

class ShutterSchedule {
 public:
  ShutterSchedule() : ShutterSchedule(ShutterParams{}) {}
  explicit ShutterSchedule(const ShutterParams& params);  // checks params

  const ShutterParams& params() const { return params_; }
  int cycle_length() const { return int(params_.cycle.size()); }
  // Time from the start of one cycle to the start of the next (s).
  double cycle_duration_s() const { return cycle_duration_; }
  // Frames per second of each cycle entry's stream (e.g. the bright-frame rate).
  double stream_rate_hz() const { return 1.0 / cycle_duration_; }
  double FrameStart(int64_t index) const;
  // One frame's record; `seed` drives the synchronisation jitter.
  ShutterFrame Frame(int64_t index, uint64_t seed = 0) const;
  std::vector<ShutterFrame> Frames(int64_t count, uint64_t seed = 0) const;

 private:
  double SwitchTime(int64_t index, uint64_t seed) const;
  double LitTime(int light, int64_t index, double exposure, uint64_t seed) const;

  ShutterParams params_;
  std::vector<double> gap_;     // per cycle entry: time to the next frame start
  std::vector<double> offset_;  // per cycle entry: start within the cycle
  double cycle_duration_ = 0;
};

}  // namespace lt

// Shutter schedule: timestamps, the thesis's frame rates, and the fraction of
// each light's on-time inside each exposure (laser bleeding into bright frames).
#include "sensor/shutter.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sensor/param_error.h"

namespace lt {
namespace {

TEST(Shutter, AlternatingTimestamps) {
  ShutterSchedule s(AlternatingShutter(2e-3, 100e-6, 9.665e-3));
  auto frames = s.Frames(6);
  for (int i = 0; i < 6; ++i) {
    const auto& f = frames[size_t(i)];
    EXPECT_EQ(f.index, i);
    EXPECT_NEAR(f.t_start_s, i * 9.665e-3, 1e-15);
    EXPECT_NEAR(f.t_end_s - f.t_start_s, i % 2 == 0 ? 2e-3 : 100e-6, 1e-15);
    EXPECT_EQ(f.label, i % 2 == 0 ? "bright" : "dim");
    EXPECT_EQ(f.laser_on, i % 2 == 1);
    EXPECT_EQ(f.led_on, i % 2 == 0);
    // Perfect synchronisation: commanded lights are lit the whole exposure, others never.
    EXPECT_DOUBLE_EQ(f.laser_fraction, f.laser_on ? 1.0 : 0.0);
    EXPECT_DOUBLE_EQ(f.led_fraction, f.led_on ? 1.0 : 0.0);
  }
}

TEST(Shutter, ExposureChangeOverheadReproducesTheThesisFrameRates) {
  // Thesis table 5.1 (1000x700): 51.739 bright fps at constant exposure, 29.738
  // when the exposure is set every frame (14.3 ms more per bright/dim pair).
  const double period = 1.0 / (2 * 51.739);
  ShutterParams constant = AlternatingShutter(100e-6, 100e-6, period);
  constant.exposure_change_overhead_s = 7.15e-3;
  EXPECT_NEAR(ShutterSchedule(constant).stream_rate_hz(), 51.739, 1e-9);  // no change, no overhead
  ShutterParams variable = AlternatingShutter(200e-6, 100e-6, period);
  variable.exposure_change_overhead_s = 7.15e-3;  // two changes per pair
  ShutterSchedule s(variable);
  EXPECT_NEAR(s.stream_rate_hz(), 29.738, 0.01);
  EXPECT_NEAR(s.FrameStart(1) - s.FrameStart(0), period + 7.15e-3, 1e-15);
  EXPECT_NEAR(s.FrameStart(4), 2 * s.cycle_duration_s(), 1e-15);
}

TEST(Shutter, LongExposureStretchesTheFrame) {
  ShutterParams p;
  p.cycle = {ShutterFrameSpec{"a", 30e-3, true, false, false, std::nullopt},
             ShutterFrameSpec{"b", 1e-3, false, false, true, std::nullopt}};
  p.frame_period_s = 10e-3;
  ShutterSchedule s(p);
  EXPECT_NEAR(s.FrameStart(1), 30e-3, 1e-15);
  EXPECT_NEAR(s.FrameStart(2), 40e-3, 1e-15);
}

TEST(Shutter, LateSwitchingBleedsTheLaserIntoBrightFrames) {
  ShutterParams p = AlternatingShutter(2e-3, 100e-6, 10e-3);
  p.sync_offset_s = 50e-6;  // lights switch 50 us after each exposure starts
  ShutterSchedule s(p);
  ShutterFrame bright0 = s.Frame(0), dim = s.Frame(1), bright = s.Frame(2);
  EXPECT_NEAR(bright0.led_fraction, (2e-3 - 50e-6) / 2e-3, 1e-12);  // LED comes on late
  EXPECT_EQ(bright0.laser_fraction, 0.0);                             // nothing on before frame 0
  EXPECT_NEAR(dim.laser_fraction, 50e-6 / 100e-6, 1e-12);
  EXPECT_NEAR(dim.led_fraction, 50e-6 / 100e-6, 1e-12);               // LED of the bright frame lingers
  EXPECT_NEAR(bright.laser_fraction, 50e-6 / 2e-3, 1e-12);            // the bleeding
  EXPECT_NEAR(bright.laser_on_time_s(), 50e-6, 1e-15);
  EXPECT_NEAR(bright.led_fraction, (2e-3 - 50e-6) / 2e-3, 1e-12);
}

TEST(Shutter, EarlySwitchingBleedsTheNextFrameIntoTheEndOfALongExposure) {
  ShutterParams p = AlternatingShutter(9.99e-3, 100e-6, 10e-3);
  p.sync_offset_s = -30e-6;  // switch 30 us before the next exposure: 20 us inside this one
  ShutterSchedule s(p);
  ShutterFrame bright = s.Frame(2);
  EXPECT_NEAR(bright.laser_fraction, 20e-6 / 9.99e-3, 1e-12);
  EXPECT_NEAR(bright.led_fraction, (9.99e-3 - 20e-6) / 9.99e-3, 1e-12);
  EXPECT_NEAR(s.Frame(3).laser_fraction, 1.0, 1e-12);  // the short dim exposure is fully lit
}

TEST(Shutter, JitterBleedsOnAverageSigmaOverRootTwoPi) {
  ShutterParams p = AlternatingShutter(1e-3, 100e-6, 10e-3);
  p.sync_jitter_s = 20e-6;
  ShutterSchedule s(p);
  const int pairs = 4000;
  double bleed = 0;
  for (int i = 1; i <= pairs; ++i) bleed += s.Frame(2 * i, 7).laser_on_time_s();
  // E[max(0, J)] = σ/√(2π) for J ~ N(0, σ²) (the ±5σ clamp changes it by < 1e-5);
  // its standard deviation is 0.584σ, so the mean of 4000 has a standard error of 0.009σ.
  EXPECT_NEAR(bleed / pairs, 20e-6 / std::sqrt(2 * M_PI), 0.04 * 20e-6);
  // Deterministic per seed.
  EXPECT_EQ(s.Frame(10, 7).laser_fraction, s.Frame(10, 7).laser_fraction);
  EXPECT_NE(s.Frame(10, 7).switch_time_s, s.Frame(10, 8).switch_time_s);
}

TEST(Shutter, CycleEntriesCarryTheirGain) {
  ShutterParams p = AlternatingShutter(1e-3, 100e-6, 10e-3);
  p.cycle[1].analog_gain_db = 12.0;
  ShutterSchedule s(p);
  EXPECT_FALSE(s.Frame(0).analog_gain_db);
  ASSERT_TRUE(s.Frame(3).analog_gain_db);
  EXPECT_EQ(*s.Frame(3).analog_gain_db, 12.0);
}

TEST(Shutter, InvalidParametersNameTheirKey) {
  auto key_of = [](ShutterParams p) {
    try {
      ShutterSchedule s(p);
    } catch (const ParamError& e) {
      return e.key();
    }
    return std::string();
  };
  ShutterParams p;
  p.cycle.clear();
  EXPECT_EQ(key_of(p), "cycle");
  p = ShutterParams{};
  p.cycle[0].exposure_s = 0;
  EXPECT_EQ(key_of(p), "cycle/0/exposure_us");
  p = ShutterParams{};
  p.sync_jitter_s = 2e-3;  // 5σ = 10 ms > half the 16.7 ms period
  EXPECT_EQ(key_of(p), "sync_offset_us");
}

}  // namespace
}  // namespace lt

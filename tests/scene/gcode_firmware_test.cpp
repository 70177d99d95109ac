// G-code commands that real files carry beyond the slicers' own: printer macros and
// host commands, probing that takes time on the printer, and the firmwares' offsets
// (babystepping M290, G92.1-G92.3, machine coordinates G53, work offsets G54-G59 set
// by G10 L2/L20).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "scene/gcode.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using ::testing::HasSubstr;
constexpr double kMm = 1e-3;

// Klipper's user macros are skipped and named, one warning per distinct name (what
// they do is in the printer's configuration); Klipper's own motionless commands are
// skipped silently; "_NAME" (a hidden macro) and OctoPrint's "@pause" (Cura's Pause
// at Height script) do not stop the read.
TEST(GcodeFirmware, UnknownMacrosAreWarnedOncePerName) {
  Toolpath p = ParseGcode(
      "PRINT_START BED=60 EXTRUDER=210\n"
      "_CLEAN_NOZZLE\n"
      "EXCLUDE_OBJECT_DEFINE NAME=cube CENTER=10,10 POLYGON=[[0,0],[20,0],[20,20]]\n"
      "SET_VELOCITY_LIMIT ACCEL=5000\n"
      "G1 X10 Y10 F6000\n"
      "@pause now change filament\n"
      "G1 X20 E1\n"
      "_CLEAN_NOZZLE\n"
      "print_end\n",
      "klipper.gcode");
  ASSERT_EQ(p.segments.size(), 2u);
  EXPECT_TRUE(p.segments[1].end_m.isApprox(Eigen::Vector3d(20, 10, 0) * kMm));
  ASSERT_EQ(p.warnings.size(), 3u);
  EXPECT_EQ(p.warnings[0].line, 1);
  EXPECT_EQ(p.warnings[0].count, 1);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("PRINT_START skipped: a command the reader does not know"));
  EXPECT_EQ(p.warnings[1].line, 2);
  EXPECT_EQ(p.warnings[1].count, 2);
  EXPECT_THAT(p.warnings[1].text, HasSubstr("_CLEAN_NOZZLE skipped"));
  EXPECT_EQ(p.warnings[2].line, 9);
  EXPECT_THAT(p.warnings[2].text, HasSubstr("PRINT_END skipped"));
  EXPECT_EQ(p.skipped_commands.at("@PAUSE"), 1u);
  EXPECT_EQ(p.skipped_commands.at("EXCLUDE_OBJECT_DEFINE"), 1u);
}

// Probing takes no time in the toolpath though it takes seconds to minutes on the
// printer (how long is the printer's configuration): one warning, first line and count.
TEST(GcodeFirmware, ProbingIsWarnedToTakeNoTime) {
  Toolpath p = ParseGcode("G28\nG29\nG1 X10 Y10 Z1 F6000\nG30\nG1 Z0.2\nBED_MESH_CALIBRATE\nG1 Z0.3\n", "probe.gcode");
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 2);
  EXPECT_EQ(p.warnings[0].count, 3);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("G29 (probing, levelling) takes no time in the toolpath"));
  // A tool parked in its dock (Prusa XL) is no probing.
  EXPECT_TRUE(ParseGcode("P0 S1 L2 D0\nG1 X1 Y1 Z1 F600\n", "xl.gcode").warnings.empty());
}

}  // namespace
}  // namespace lt

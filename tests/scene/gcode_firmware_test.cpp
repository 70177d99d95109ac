// G-code commands that real files carry beyond the slicers' own: printer macros and
// host commands, probing that takes time on the printer, and the firmwares' offsets
// (babystepping M290, G92.1-G92.3, machine coordinates G53, work offsets G54-G59 set
// by G10 L2/L20).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

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
  // An expression (RepRapFirmware's meta commands, a placeholder the slicer left) is named.
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X1 F600\nG1 X{var.x} Y2\n", "rrf.gcode"); }),
              HasSubstr("rrf.gcode:2: X is an expression (\"{var.x} Y2\""));
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
  // A tool parked in its dock (Prusa XL) is no probing, nor is Marlin's nozzle park
  // (G27) or clean (G12), which end at a place of the printer's configuration: the
  // position is unknown after them, as after probing.
  EXPECT_TRUE(ParseGcode("P0 S1 L2 D0\nG1 X1 Y1 Z1 F600\n", "xl.gcode").warnings.empty());
  for (const char* park : {"G27 P2", "G12 P1 S2"}) {
    Toolpath q = ParseGcode(std::string("G1 X5 Y5 Z5 F600\n") + park + "\nG91\nG1 Z1\n", "park.gcode");
    ASSERT_EQ(q.warnings.size(), 1u) << park;
    EXPECT_THAT(q.warnings[0].text, HasSubstr("left unknown in Z")) << park;
    EXPECT_EQ(q.skipped_commands.size(), 1u) << park;
  }
  EXPECT_EQ(ParseGcode("G35\n", "tram.gcode").warnings.at(0).count, 1);
  // G29 that loads, fills, activates or saves a mesh moves nothing: the position stays
  // known and nothing is warned (RepRapFirmware's "G29 S1", UBL's L and A, Prusa's P3.2).
  Toolpath mesh = ParseGcode("G28\nG29 L0\nG29 A\nG29 S1\nG29 P3.2\nG29 P3.13\nG91\nG1 Z5 F600\n", "mesh.gcode");
  EXPECT_TRUE(mesh.warnings.empty());
  EXPECT_EQ(mesh.skipped_commands.at("G29"), 5u);
  // These probe: Prusa's area, RepRapFirmware's S0, Bambu's adaptive area, UBL's tilt.
  for (const char* probe : {"G29 P1 X23 Y5 W80 H20 C", "G29 S0", "G29 A X10 Y10 I5 J5", "G29 J", "G29 L1 J"}) {
    Toolpath q = ParseGcode(std::string("G28\n") + probe + "\nG1 X1 Y1 Z1 F600\n", "p.gcode");
    ASSERT_EQ(q.warnings.size(), 1u) << probe;
    EXPECT_EQ(q.skipped_commands.count("G29"), 0u) << probe;
  }
}

// The end points of a toolpath's segments, in mm.
std::vector<Eigen::Vector3d> Ends(const Toolpath& p) {
  std::vector<Eigen::Vector3d> ends;
  for (const ToolpathSegment& s : p.segments) ends.push_back(s.end_m / kMm);
  return ends;
}

// M290 (babystepping: Marlin, RepRapFirmware) moves the nozzle now and shifts every later
// move by as much, until the axis is homed; RepRapFirmware's R0 makes S absolute. It was
// skipped: the print ran 0.05 mm below the printer's.
TEST(GcodeFirmware, BabysteppingShiftsLaterMovesUntilHoming) {
  Toolpath p = ParseGcode(
      "G1 X10 Y10 Z0.2 F600\n"
      "M290 Z0.05\n"       // up 0.05 now
      "G1 X20 E1\n"        // at 0.25
      "M290 S-0.02\n"      // S is Z: 0.23
      "G1 Z1\n"            // 1.03
      "M290 R0 S0.1\n"     // absolute: 0.1 in all, 1.1
      "G28 Z\n"            // homing clears it
      "G1 Z1\n",
      "babystep.gcode");
  const std::vector<Eigen::Vector3d> ends = Ends(p);
  ASSERT_EQ(ends.size(), 8u);
  const double z[] = {0.2, 0.25, 0.25, 0.23, 1.03, 1.1, 0, 1};
  for (size_t i = 0; i < ends.size(); ++i) EXPECT_NEAR(ends[i].z(), z[i], 1e-12) << i;
  EXPECT_EQ(p.segments[1].line, 2);
  EXPECT_EQ(p.segments[1].extruded_m, 0);
  EXPECT_THAT(ErrorOf([] { ParseGcode("M290 S0.1 Z0.1\n", "b.gcode"); }), HasSubstr("b.gcode:1: M290 takes S or Z"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("M290 Q1\n", "b.gcode"); }), HasSubstr("b.gcode:1: M290 takes no parameter Q"));
}

// G92.1 clears G92's offset, G92.2 clears and keeps it, G92.3 restores it (RS-274,
// RepRapFirmware, Marlin's G92.1); G53 puts one line's move in machine coordinates.
// All were skipped: after "G92 X0" at X10, "G92.1 / G1 X5" went to 15.
TEST(GcodeFirmware, G92ResetsAndMachineCoordinates) {
  Toolpath p = ParseGcode(
      "G1 X10 F600\n"
      "G92 X0\n"         // logical 0 at machine 10
      "G53 G1 X5\n"      // machine 5
      "G1 X5\n"          // machine 15
      "G92.2\n"          // cleared, kept
      "G1 X1\n"          // machine 1
      "G92.3\n"          // restored
      "G1 X1\n"          // machine 11
      "G92.1\n"          // cleared
      "G53\n"            // alone on its line: nothing
      "G1 X2\n",         // machine 2
      "offsets.gcode");
  const std::vector<Eigen::Vector3d> ends = Ends(p);
  ASSERT_EQ(ends.size(), 6u);
  const double x[] = {10, 5, 15, 1, 11, 2};
  for (size_t i = 0; i < ends.size(); ++i) EXPECT_NEAR(ends[i].x(), x[i], 1e-12) << i;
  EXPECT_THAT(ErrorOf([] { ParseGcode("G92.1 X0\n", "o.gcode"); }), HasSubstr("o.gcode:1: G92.1 takes no parameter X"));
}

// Work coordinate systems (G54-G59, G59.1-G59.3; RRF and CNC-style files): G10 L2 sets a
// system's origin in machine coordinates, G10 L20 the origin that makes the current
// position the given value; homing keeps them. G10 alone is still a firmware retraction
// and G10 P.. S.. (RepRapFirmware's tool temperatures) is skipped. All were skipped:
// "G10 L2 P2 X10 / G55 / G1 X10" went to 10, not 20.
TEST(GcodeFirmware, WorkOffsetsAreSetByG10L2AndL20) {
  Toolpath p = ParseGcode(
      "G10 L2 P2 X10 Y5\n"
      "G10 P0 S210 R170\n"
      "G55\n"
      "G1 X10 Y0 F600\n"     // machine (20, 5)
      "G54\n"
      "G1 X10\n"             // machine (10, 5): Y not named
      "G10 L20 P7 X0\n"      // G59.1: here is X0
      "G59.1\n"
      "G1 X2\n"              // machine 12
      "G28 X\n"              // machine 0
      "G1 X0\n"              // machine 10
      "G10\n",               // firmware retraction
      "wcs.gcode");
  const std::vector<Eigen::Vector3d> ends = Ends(p);
  ASSERT_EQ(ends.size(), 6u);
  EXPECT_TRUE(ends[0].isApprox(Eigen::Vector3d(20, 5, 0)));
  EXPECT_TRUE(ends[1].isApprox(Eigen::Vector3d(10, 5, 0)));
  EXPECT_NEAR(ends[2].x(), 12, 1e-12);
  EXPECT_NEAR(ends[3].x(), 0, 1e-12);
  EXPECT_NEAR(ends[4].x(), 10, 1e-12);
  EXPECT_EQ(p.segments[5].gcode, 10);
  EXPECT_EQ(p.skipped_commands.at("G10"), 1u);
  EXPECT_THAT(ErrorOf([] { ParseGcode("G10 L2 P10 X1\n", "w.gcode"); }),
              HasSubstr("w.gcode:1: G10 L2 P must be a coordinate system 1-9"));
}

// Bambu Studio's start scripts (X1, P1): "M221 X0 Y0 Z0" switches soft endstops off (it
// was "M221 takes no parameter X", which stopped the read), and "G29.1 Z-0.02" sets the
// z-trim for a textured plate, an offset of later moves (not cumulative; Z0 clears it;
// it was skipped, the first layer 0.02 mm high).
TEST(GcodeFirmware, BambuZTrimAndSoftEndstops) {
  Toolpath p = ParseGcode(
      "M221 S100\n"
      "M221 X0 Y0 Z0 ; turn off soft endstop\n"
      "G29.1 Z+0.0 ; clear z-trim value first\n"
      "G1 X1 Z0.2 F600\n"
      "G29.1 Z-0.02\n"
      "G29.1 Z-0.02\n"
      "G1 X2 Z0.2\n"
      "G1 Z0.4\n"
      "G29.1 Z0\n"
      "G1 Z0.6\n",
      "bambu.gcode");
  const std::vector<Eigen::Vector3d> ends = Ends(p);
  ASSERT_EQ(ends.size(), 4u);
  const double z[] = {0.2, 0.18, 0.38, 0.6};
  for (size_t i = 0; i < ends.size(); ++i) EXPECT_NEAR(ends[i].z(), z[i], 1e-12) << i;
  EXPECT_EQ(p.skipped_commands.at("M221"), 1u);
  // A G29.1 with other words is no z-trim: skipped.
  EXPECT_EQ(ParseGcode("G29.1 Q\n", "b.gcode").skipped_commands.at("G29.1"), 1u);
}

// A coordinate no machine reaches (1 km and more: a corrupted number) is refused
// naming the line, for lines and arcs alike: its squares overflowed (a move of
// infinite duration), and a full circle 100 km wide ran for minutes.
TEST(GcodeFirmware, CoordinatesBeyondAnyMachineAreRefused) {
  const std::string huge = "1" + std::string(200, '0');
  EXPECT_THAT(ErrorOf([&] { ParseGcode("G1 X10 F600\nG1 X" + huge + " E1\n", "far.gcode"); }),
              HasSubstr("far.gcode:2: X1e+200 puts the nozzle at 1e+200 mm, beyond any machine's reach (1 km)"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("G91\nG1 X600000 F600\nG1 X600000\n", "rel.gcode"); }),
              HasSubstr("rel.gcode:3: X600000 puts the nozzle at 1200000 mm"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X10 Y0 F600\nG2 X10 Y0 I-100000000 J0 E1\n", "arc.gcode"); }),
              HasSubstr("arc.gcode:2: G2 radius 1e+08 takes the arc beyond any machine's reach"));
  // A large part's coordinates (a 10 m gantry, in mm) and a 400 m arc are read.
  EXPECT_NO_THROW(ParseGcode("G1 X10000 Y5000 F6000\nG2 X10000 Y5000.001 I-400000 J0\n", "big.gcode"));
}

}  // namespace
}  // namespace lt

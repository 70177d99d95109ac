// G-code the reader can only approximate, and says so (Toolpath::warnings): an
// unclosed '(' comment, relative moves from a position that probing (G29, G80, ...)
// left unknown, extra axes (U, V, W, C) the toolpath does not model; and Cura's
// UltiGCode flavour, whose E is a volume.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene/bead_geometry.h"
#include "scene/gcode.h"
#include "scene/motion.h"
#include "scene/motion_gcode.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using ::testing::HasSubstr;
using ::testing::Not;
constexpr double kMm = 1e-3;

// Marlin (PAREN_COMMENTS) and RepRapFirmware end a '(' comment without ')' at the
// line's end: the words before it are read, the rest is not, and a warning names the
// first such line and counts them.
TEST(GcodeApproximations, UnclosedParenCommentRunsToTheLineEndWithAWarning) {
  Toolpath p = ParseGcode(
      "G1 X10 F600 (fast Y5\n"  // Y5 is inside the comment
      "G1 X20 (closed) Y7\n"
      "(unclosed again\n"
      "G1 X30 Y7 E1\n",
      "paren.gcode");
  ASSERT_EQ(p.segments.size(), 3u);
  EXPECT_TRUE(p.segments[0].end_m.isApprox(Eigen::Vector3d(10, 0, 0) * kMm));
  EXPECT_TRUE(p.segments[1].end_m.isApprox(Eigen::Vector3d(20, 7, 0) * kMm));
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 1);
  EXPECT_EQ(p.warnings[0].count, 2);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("\"(fast Y5\" is not read"));
  EXPECT_TRUE(ParseGcode("G1 X10 F600 (closed)\n", "p.gcode").warnings.empty());
}

// Probing ends where the firmware stops: X, Y and Z are unknown until an absolute move
// (or homing) sets each. A relative move on an unknown axis is built from the last
// known position, with a warning naming its line and the probing command's.
TEST(GcodeApproximations, ProbingLeavesThePositionUnknownUntilAnAbsoluteMove) {
  Toolpath p = ParseGcode(
      "G28\n"
      "G1 X50 Y50 Z10 F6000\n"
      "G29 ; auto bed levelling\n"
      "G91\n"
      "G1 Z5\n"  // Z unknown: warned
      "G90\n"
      "G1 X10 Y10\n"  // X, Y known again
      "G91\n"
      "G1 Z-1\n"  // Z still unknown: counted
      "G1 X1\n"   // X known: fine
      "G90\n",
      "probe.gcode");
  // The probing's own warning first (line 3: it takes no time), then the relative move's.
  ASSERT_EQ(p.warnings.size(), 2u);
  EXPECT_EQ(p.warnings[0].line, 3);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("G29 (probing, levelling) takes no time"));
  EXPECT_EQ(p.warnings[1].line, 5);
  EXPECT_EQ(p.warnings[1].count, 2);
  EXPECT_THAT(p.warnings[1].text, HasSubstr("G1 moves relative to a position G29 (line 3) left unknown in Z"));
  EXPECT_THAT(p.warnings[1].text, HasSubstr("last known position X50 Y50 Z10"));
  EXPECT_EQ(p.skipped_commands.count("G29"), 0u);

  // The warning about a relative move from an unknown position ("" when none).
  auto relative = [](const std::string& g) {
    for (const ToolpathWarning& w : ParseGcode(g, "p.gcode").warnings) {
      if (w.text.find("moves relative") != std::string::npos) return w.text;
    }
    return std::string();
  };
  // Homing and absolute moves make the axes known; G80 in a CNC header cancels a cycle.
  EXPECT_EQ(relative("G29\nG28\nG91\nG1 X1 Y1 Z5 F600\n"), "");
  EXPECT_EQ(relative("G29\nG1 X0 Y0 Z1 F600\nG91\nG1 X1 Y1 Z5\n"), "");
  EXPECT_TRUE(ParseGcode("G17 G80 G90\nG91\nG1 X1 F600\n", "p.gcode").warnings.empty());
  // Prusa's mesh levelling, Klipper's macros, a straight probe, an arc's centre.
  EXPECT_THAT(relative("G80\nG91\nG1 X1 F600\n"), HasSubstr("G80 (line 1) left unknown in X"));
  EXPECT_THAT(relative("BED_MESH_CALIBRATE\nG91\nG1 Z1 F600\n"),
              HasSubstr("BED_MESH_CALIBRATE (line 1) left unknown in Z"));
  EXPECT_THAT(relative("G38.2 Z-10 F100\nG91\nG1 Z1\n"), HasSubstr("G38.2 (line 1) left unknown in Z"));
  EXPECT_THAT(relative("G380 S2 Z-5 F300\nG91\nG1 Z5\n"), HasSubstr("G380 (line 1) left unknown in Z"));
  EXPECT_THAT(relative("G29\nG2 X10 Y0 I5 J0 F600\n"), HasSubstr("G2 moves relative to a position G29"));
  // Prusa XL: a tool parked (P0) or changed without return (D0) leaves the head at the
  // dock; no probing there (no warning about time).
  auto warnings = [](const std::string& g) { return ParseGcode(g, "p.gcode").warnings; };
  ASSERT_EQ(warnings("P0 S1 L2 D0\nG91\nG1 X1 F600\n").size(), 1u);
  EXPECT_THAT(warnings("P0 S1 L2 D0\nG91\nG1 X1 F600\n").at(0).text, HasSubstr("P0 (line 1) left unknown in X"));
  EXPECT_THAT(warnings("T1 S1 L0 D0\nG91\nG1 X1 F600\n").at(0).text, HasSubstr("T1 (line 1) left unknown in X"));
  EXPECT_TRUE(warnings("T1\nG91\nG1 X1 F600\n").empty());
}

// U, V, W and C (a tool changer's coupler, a second carriage, a rotary axis) are not
// modelled: ignored with one warning that names them, unless one moves while the line
// extrudes, which would change the printed path.
TEST(GcodeApproximations, ExtraAxesAreIgnoredUnlessTheyMoveWhileExtruding) {
  Toolpath p = ParseGcode(
      "G1 X10 Y10 F6000\n"
      "G1 U10\n"           // RepRapFirmware tool changer: park
      "G1 C-50 F5000\n"    // the coupler locks
      "G92 U0\n"
      "G28 C\n"            // homes C only: X, Y, Z stay
      "G1 X20 U0 E1\n"     // U named but not moving: a print move
      "G28 W\n",           // Prusa firmware: home all without mesh levelling (W is no axis)
      "toolchanger.gcode");
  ASSERT_EQ(p.segments.size(), 4u);  // the two moves, then X and Y home
  EXPECT_TRUE(p.segments[1].end_m.isApprox(Eigen::Vector3d(20, 10, 0) * kMm));
  EXPECT_NEAR(p.segments[1].t_start_s, 10 * std::sqrt(2.0) / 100, 1e-12);  // C's move took no time
  EXPECT_NEAR(p.segments[1].extruded_m, 1 * kMm, 1e-15);
  EXPECT_EQ(p.segments[3].gcode, 28);
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 2);
  EXPECT_EQ(p.warnings[0].count, 5);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("axis U, C ignored"));

  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X10 F600\nG1 X20 V5 E1\n", "v.gcode"); }),
              HasSubstr("v.gcode:2: G1 moves the V axis while it extrudes"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("M83\nG3 X0 Y0 I5 J0 W1 E2 F600\n", "w.gcode"); }),
              HasSubstr("w.gcode:2: G3 moves the W axis while it extrudes"));
}

// Cura's UltiGCode flavour (Ultimaker 2): E in mm^3, no M200. Held as lengths of
// Ultimaker's 2.85 mm filament; the beads hold the volume.
TEST(GcodeApproximations, UltiGCodeExtrusionIsVolume) {
  Toolpath p = ParseGcode(";FLAVOR:UltiGCode\n;TIME:12\n;MATERIAL:6\nG90\nG1 X10 E6 F600\nG10\nG11\n", "um2.gcode");
  ASSERT_EQ(p.segments.size(), 3u);
  const double area_mm2 = M_PI * 0.25 * 2.85 * 2.85;
  EXPECT_NEAR(p.segments[0].extruded_m, 6 / area_mm2 * kMm, 1e-15);
  EXPECT_NEAR(p.filament_diameter_m, 2.85 * kMm, 1e-15);
  Mesh bead = BeadMeshUpTo(p, p.segments[0].t_end_s, BeadOptions{.layer_height_m = 0.2e-3});
  EXPECT_NEAR(MeshVolume(bead), 6e-9, 1e-3 * 6e-9);  // 6 mm^3
  // Cura's other flavours are lengths.
  EXPECT_NEAR(ParseGcode(";FLAVOR:Marlin\nG1 X10 E6 F600\n", "m.gcode").segments[0].extruded_m, 6 * kMm, 1e-15);
}

// M221's flow percentage scales what the extruder feeds (PrusaSlicer's MK3S start
// script sets "M221 S95" for layers of 0.075 mm and more), M220's the feed rates
// (B saves, R restores: Marlin); Marlin's M208 sets G11's extra length and feed.
TEST(GcodeApproximations, FlowAndSpeedPercentagesAndRecoverySettings) {
  Toolpath p = ParseGcode(
      "M83\n"
      "G1 X10 E1 F600\n"  // 10 mm/s, 1 mm
      "M221 S95\n"
      "M220 B S50\n"      // B saves 100 % before S sets 50 %
      "G1 X20 E1\n"       // 0.95 mm at 5 mm/s: 2 s
      "G1 E-0.5 F1800\n"  // retraction, scaled too: 0.475 mm at 15 mm/s
      "M220 R\n"
      "M221 S100 T0\n"
      "M221 T1 S50\n"   // another tool's flow: not T0's
      "G1 X30 E1 F600\n"
      "M207 S2 F1800\n"
      "M208 S0.5 F600\n"
      "M208 X0:200 Y0:200\n"  // RepRapFirmware's axis limits
      "G10\nG11\n"
      "T1\nG1 X40 E1\n",  // tool 1 at its 50 %
      "flow.gcode");
  ASSERT_EQ(p.segments.size(), 7u);
  EXPECT_NEAR(p.segments[0].extruded_m, 1 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[1].extruded_m, 0.95 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[1].Duration(), 2.0, 1e-12);
  EXPECT_NEAR(p.segments[2].extruded_m, -0.475 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[2].Duration(), 0.475 / 15, 1e-12);
  EXPECT_NEAR(p.segments[3].extruded_m, 1 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[3].Duration(), 1.0, 1e-12);        // M220 R: 100 % again
  EXPECT_NEAR(p.segments[5].extruded_m, 2.5 * kMm, 1e-15);  // S2 + M208 S0.5
  EXPECT_NEAR(p.segments[5].Duration(), 0.25, 1e-12);       // at M208's 10 mm/s
  EXPECT_NEAR(p.segments[6].extruded_m, 0.5 * kMm, 1e-15);
  EXPECT_EQ(p.skipped_commands.at("M208"), 1u);
  EXPECT_THAT(ErrorOf([] { ParseGcode("M221 S-5\n", "f.gcode"); }), HasSubstr("f.gcode:1: M221 S"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("M220 S0\n", "f.gcode"); }), HasSubstr("f.gcode:1: M220 S"));
}

// Klipper's firmware retraction takes its settings from SET_RETRACTION (mm and mm/s),
// which was skipped: G10/G11 ran with Marlin's 3 mm defaults.
TEST(GcodeApproximations, KlipperSetRetractionSetsG10AndG11) {
  Toolpath p = ParseGcode(
      "SET_RETRACTION RETRACT_LENGTH=0.8 RETRACT_SPEED=40 UNRETRACT_EXTRA_LENGTH=0.1 UNRETRACT_SPEED=20\n"
      "G1 X10 F600\nG10\nG11\n",
      "klipper.gcode");
  ASSERT_EQ(p.segments.size(), 3u);
  EXPECT_NEAR(p.segments[1].extruded_m, -0.8 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[1].Duration(), 0.02, 1e-12);
  EXPECT_NEAR(p.segments[2].extruded_m, 0.9 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[2].Duration(), 0.045, 1e-12);
  EXPECT_TRUE(p.firmware_retraction_set);
  EXPECT_EQ(p.skipped_commands.count("SET_RETRACTION"), 0u);
  EXPECT_THAT(ErrorOf([] { ParseGcode("SET_RETRACTION RETRACT_SPEED=0\n", "k.gcode"); }),
              HasSubstr("k.gcode:1: SET_RETRACTION RETRACT_SPEED must be a number > 0"));
}

// Arcs in the ZX (G18: centre offsets K, I) and YZ (G19: J, K) planes, as RS-274 and
// Marlin's CNC_WORKSPACE_PLANES turn them: straight chords within 1 um of the arc (they
// were refused: "G2 outside the XY plane (G18/G19) is not supported").
TEST(GcodeApproximations, ArcsInTheZxAndYzPlanesAreChords) {
  Toolpath p = ParseGcode("G1 X10 Z5 F600\nG18\nG2 X20 K0 I5 E2\nG19\nG3 Y10 Z5 J5 K0\nG17\n", "planes.gcode");
  // G18 G2: a half circle of radius 5 about (x 15, z 5), clockwise seen from +y: through z 0.
  double t_half = 0, e = 0, t0 = 0, t1 = 0;
  for (const ToolpathSegment& s : p.segments) {
    if (s.line != 3) continue;
    EXPECT_EQ(s.gcode, 2);
    if (t0 == 0) t0 = s.t_start_s;
    t1 = s.t_end_s;
    e += s.extruded_m;
    for (double u : {0.0, 0.5, 1.0}) {
      const Eigen::Vector3d q = s.PointAt(u) / kMm;
      EXPECT_NEAR(std::hypot(q.x() - 15, q.z() - 5), 5, 1.01e-3);
      EXPECT_NEAR(q.y(), 0, 1e-12);
    }
  }
  t_half = 0.5 * (t0 + t1);
  EXPECT_NEAR(t1 - t0, 5 * M_PI / 10, 2e-4);  // 15.708 mm at 10 mm/s (the chords 7e-5 shorter)
  EXPECT_NEAR(e, 2 * kMm, 1e-15);
  EXPECT_TRUE(p.PositionAt(t_half).isApprox(Eigen::Vector3d(15, 0, 0) * kMm, 1e-3));
  // G19 G3 from (20, 0, 5): centre (y 5, z 5), counter-clockwise seen from +x, to y 10.
  const ToolpathSegment& last = p.segments.back();
  EXPECT_EQ(last.line, 5);
  EXPECT_TRUE(last.end_m.isApprox(Eigen::Vector3d(20, 10, 5) * kMm));
  EXPECT_NEAR(p.Duration() - t1, 5 * M_PI / 10, 2e-4);
}

// Klipper's SET_GCODE_OFFSET shifts where later absolute moves land (and homing
// keeps it); MOVE=1 moves there at once. It was skipped: the nozzle ran 0.05 mm low.
TEST(GcodeApproximations, KlipperGcodeOffsetShiftsLaterAbsoluteMoves) {
  Toolpath p = ParseGcode(
      "G28\nG1 X10 Y10 Z0.2 F600\n"
      "SET_GCODE_OFFSET Z=0.05\n"
      "G1 X20 E1\n"  // Z not named: stays at 0.2
      "G1 Z0.4\n"    // 0.45
      "SET_GCODE_OFFSET Z_ADJUST=-0.02 MOVE=1 MOVE_SPEED=5\n"
      "G91\nG1 X1\nG90\n"
      "G28 Z\nG1 Z1\n",
      "offset.gcode");
  ASSERT_EQ(p.segments.size(), 7u);
  EXPECT_NEAR(p.segments[1].end_m.z(), 0.2 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[2].end_m.z(), 0.45 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[3].end_m.z(), 0.43 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[3].Duration(), 0.02 / 5, 1e-12);
  EXPECT_TRUE(p.segments[4].end_m.isApprox(Eigen::Vector3d(21, 10, 0.43) * kMm));
  EXPECT_EQ(p.segments[5].gcode, 28);
  EXPECT_NEAR(p.segments[6].end_m.z(), 1.03 * kMm, 1e-15);
  EXPECT_EQ(p.skipped_commands.count("SET_GCODE_OFFSET"), 0u);
  EXPECT_THAT(ErrorOf([] { ParseGcode("SET_GCODE_OFFSET Z=abc\n", "k.gcode"); }),
              HasSubstr("k.gcode:1: SET_GCODE_OFFSET Z must be a number"));
}

// The warnings reach the motion's notes, which `info` and `render` print: file:line,
// the text and the count.
TEST(GcodeApproximations, MotionNotesCarryTheWarnings) {
  test::TempDir dir;
  test::WriteText(dir / "u.gcode", "G1 X10 F600\nG1 U5\nG1 U6\nG1 X20 E1\n");
  json::Document doc = json::Document::Parse(R"({"type": "gcode", "file": "u.gcode"})", "scene.json", dir.path());
  std::string notes;
  for (const std::string& note : MotionNotes(ParseMotion(doc.Root()))) notes += note + "\n";
  EXPECT_THAT(notes, HasSubstr("u.gcode:2: axis U ignored"));
  EXPECT_THAT(notes, HasSubstr("extrudes (2 times)\n"));
}

// Without M207, the note on firmware retraction gives the lengths it assumed, the
// swap retraction's (G10 S1: 13 mm) as well as the plain one's (3 mm).
TEST(GcodeApproximations, FirmwareRetractionNoteNamesTheSwapLength) {
  test::TempDir dir;
  test::WriteText(dir / "s.gcode", "M83\nG1 X10 F600 E1\nG10 S1\nG11\nG10\nG11\nG1 X20 E1\n");
  test::WriteText(dir / "p.gcode", "M83\nG1 X10 F600 E1\nG10\nG11\nG1 X20 E1\n");
  std::string swap_notes, plain_notes;
  for (const char* name : {"s.gcode", "p.gcode"}) {
    json::Document doc = json::Document::Parse(std::string(R"({"type": "gcode", "file": ")") + name + "\"}",
                                               "scene.json", dir.path());
    for (const std::string& note : MotionNotes(ParseMotion(doc.Root()))) {
      (name[0] == 's' ? swap_notes : plain_notes) += note + "\n";
    }
  }
  EXPECT_THAT(swap_notes, HasSubstr("s.gcode:3: 2 G10 and 2 G11 (firmware retraction) without M207 in the file: "
                                    "Marlin's defaults assumed (3 mm at 45 mm/s, recovered at 8 mm/s, no Z hop; 1 of "
                                    "the G10 are swap retractions (G10 S1): 13 mm, recovered at 8 mm/s)"));
  EXPECT_THAT(plain_notes, HasSubstr("no Z hop)"));
  EXPECT_THAT(plain_notes, Not(HasSubstr("swap")));
}

}  // namespace
}  // namespace lt

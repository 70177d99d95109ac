// Constructs met in the second pass over real slicers' files (docs/sequences.md, "Real
// files checked", second pass), each as a tiny excerpt in the form the file has it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "scene/bead_geometry.h"
#include "scene/gcode.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using ::testing::HasSubstr;
constexpr double kMm = 1e-3;

// Legacy Cura (15.x, "Sliced at:") copies the user's start script, here with a line
// of axis words alone: "G0 X100 Y100" then "Z10". It was "expected a command (G, M or T),
// got "Z10"": the file could not be read. The motion command is modal (RS-274; Grbl and
// RepRapFirmware read it so): Z10 is G0 Z10, warned with its line and count since Marlin
// without GCODE_MOTION_MODES ignores such a line.
TEST(GcodeRealFiles2, LegacyCuraAxisWordsWithoutCommandRepeatTheLastMotion) {
  Toolpath p = ParseGcode(
      ";Sliced at: Sun 03-07-2016 17:55:50\n;Filament used: 2.584m 20.0g\nG21\nG90\nM82\n"
      "G28 X0 Y0  ;move X/Y to min endstops\nG0 X100 Y100\nZ10\nG28 Z0\nG1 Z15.0 F100\n"
      ";LAYER:0\nG0 F10800 X48.217 Y22.131 Z0.300\nG1 F1800 X48.687 Y21.229 E0.01913\n"
      "X49 Y21 E0.03\n",
      "legacy.gcode");
  ASSERT_GE(p.segments.size(), 3u);
  EXPECT_NEAR(p.segments[1].end_m.z(), 10 * kMm, 1e-12);  // Z10 after G0 X100 Y100
  EXPECT_EQ(p.segments[1].gcode, 0);
  EXPECT_NEAR(p.segments[1].end_m.x(), 100 * kMm, 1e-12);
  EXPECT_NEAR(p.segments.back().end_m.x(), 49 * kMm, 1e-12);  // after G1: a G1 with E
  EXPECT_EQ(p.segments.back().gcode, 1);
  EXPECT_NEAR(p.segments.back().extruded_m, (0.03 - 0.01913) * kMm, 1e-12);
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 8);
  EXPECT_EQ(p.warnings[0].count, 2);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("\"Z10\": axis words without a command, read as G0"));
  // Without an earlier motion command, or after RS-274's G80 (cancel the motion mode), it is still an error.
  EXPECT_THAT(ErrorOf([] { ParseGcode("G21\nZ10\n", "z.gcode"); }),
              HasSubstr("z.gcode:2: expected a command (G, M or T), got \"Z10\""));
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X5 F600\nG17 G80 G90\nX10\n", "z.gcode"); }),
              HasSubstr("z.gcode:3: expected a command"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X5 F600\nZ1 Q2\n", "z.gcode"); }), HasSubstr("z.gcode:2:"));
}

// A slicer's "filament used" counts what its beads take: the toolpath's
// BeadFilamentLength sums the moves that lay beads, all of them or those inside the
// layers (a start script's purge line is outside: Cura's figure leaves it out,
// PrusaSlicer's counts it); retractions, primes and wipes are no beads.
TEST(GcodeRealFiles2, BeadFilamentIsWhatTheBeadsTake) {
  Toolpath p = ParseGcode(
      "M83\nG1 Z0.3 F600\nG1 X60 E9 ; purge\nG1 E-1\n;LAYER:0\nG1 X70 Y10\nG1 E1\nG1 X80 E0.5\n"
      "G1 X90 E0.25\nG1 E-0.8\n;WIPE_START\nG1 X85 E-0.2\n;WIPE_END\nG1 Z0.5\nG1 E2 ; prime in place\n",
      "beads.gcode");
  EXPECT_NEAR(p.BeadFilamentLength(false), 9.75 * kMm, 1e-12);
  EXPECT_NEAR(p.BeadFilamentLength(true), 0.75 * kMm, 1e-12);
  EXPECT_NEAR(p.ExtrudedLength(), (9.75 - 1 + 1 - 0.8 - 0.2 + 2) * kMm, 1e-12);
}

// ideaMaker states the filament's diameter once per extruder (";Filament Diameter #1:
// 2.850", a real 5.1.4 file's header has 1.750 for a Raise3D Pro3), and its filament
// compensation as "M221 T0 S90.00" before any move. The diameter was not read: the beads
// of a 2.85 mm file took the volume of 1.75 mm filament, 0.38 times what it lays.
TEST(GcodeRealFiles2, IdeaMakerFilamentDiameterAndCompensation) {
  Toolpath p = ParseGcode(
      ";Sliced by ideaMaker 5.1.4.8480, 2025-03-11 18:58:10 UTC+0100\n;Filament Diameter #1: 2.850\n"
      ";Filament Diameter #2: 1.750\n;Filament Compensation #1: 90.000\n;Firmware: RepRapFirmware\n"
      "M221 T0 S90.00\nM104 T0 S215.00\nT0\nM572 D0 S0.03\nG21\nG90\nM82\nG28\nG92 E0\n"
      ";LAYER:0\n;Z:0.300\n;HEIGHT:0.300\nG1 F2400 E-0.5000\nG0 F9000 X129.762 Y125.070\nG0 F300 Z0.300\n"
      ";TYPE:SKIRT\n;WIDTH:0.440\nG1 F1500 E0.0000\nG1 F900 X130.426 Y124.455 E0.0472\n",
      "idea.gcode");
  EXPECT_NEAR(p.filament_diameter_m, 2.85 * kMm, 1e-15);
  EXPECT_NEAR(p.BeadFilamentLength(true), 0.9 * 0.0472 * kMm, 1e-15);  // M221 T0 S90 holds for tool 0
}

// PrusaSlicer's multi-material tool change (a real excerpt, as the Material-Switching-Unit
// project's post-processor keeps it): the old filament is rammed onto the wipe tower, drawn
// 94 mm up the tube, and its tip is shaped by cooling moves that feed 5 mm and draw it back
// while the nozzle crosses the tower; nothing leaves the nozzle then. Each +5 mm move was a
// bead (4 x 5 mm of filament laid on the tower, the excerpt's beads 28.55 mm where 8.55 mm
// come out). A feed now first makes up the filament drawn back since the nozzle last laid
// plastic; a tool change loads the new filament to the nozzle.
TEST(GcodeRealFiles2, MultiMaterialCoolingMovesLayNothing) {
  Toolpath p = ParseGcode(
      "M83\nG1 Z0.2 F600\n; CP TOOLCHANGE UNLOAD\n;WIDTH:0.6\nG1  X219.250 Y189.250  \nM900 K0\nG1 F3554\n"
      "G1  X204.441  E0.686\nG1  X189.182  E0.7068\n;WIDTH:0.5\nG1 E-15 F6000\nG1 E-55.3 F5400\n"
      "G1 E-15.8 F2700\nG1 E-7.9 F1620\nM104 S205\nG1  Y186.850 \nG1  X219.250  E5 F1302\n"
      "G1  X169.918  E-5 F1404\nG1  X219.250  E5 F1505\nG1  X169.918  E-5 F1607\nG1 E2 F2000\n"
      "G1  Y186.900  F2400\nG4 S0\nT1\nG1 X200 E1 F1200\n"
      // An ordinary retraction, wipe and prime in place: the bead after it lays all it feeds.
      "G1 E-0.56 F2400\nG1 X199 E-0.24\nG1 E0.8\nG1 X190 E0.5\n"
      // A retraction that is not made up (Bambu's start script ends with G1 E-2): the next feed refills the nozzle.
      "G1 E-2\nG1 X180 E0.5\nG1 X170 E2\n",
      "mmu.gcode");
  EXPECT_NEAR(p.BeadFilamentLength(false), (0.686 + 0.7068 + 1 + 0.5 + 0.5) * kMm, 1e-12);
  int cooling_beads = 0;
  for (const ToolpathSegment& s : p.segments) cooling_beads += s.line >= 17 && s.line <= 20 && s.LaysBead();
  EXPECT_EQ(cooling_beads, 0);
  EXPECT_NEAR(p.segments.back().laid_m, 0.5 * kMm, 1e-12);  // 2 fed, 1.5 of them refill the nozzle
  EXPECT_NEAR(p.segments.back().extruded_m, 2 * kMm, 1e-12);
  EXPECT_NEAR(p.ExtrudedLength(), (0.686 + 0.7068 - 94 + 2 + 1 - 0.8 + 0.8 + 0.5 - 2 + 0.5 + 2) * kMm, 1e-12);
}

// Cura's start script for the Anycubic i3 Mega ends with a bare "G5" (a real file's:
// "M117 Printing... / G5"), with which Anycubic's firmware enables its resume after a
// power loss. It was refused as Marlin's Bezier move ("G5 ... is not supported"), so no
// file for that printer could be read; alone, G5 moves nothing and is skipped. A G5 with
// control points is a Bezier move (since the sixth pass, GcodeRealFiles6).
TEST(GcodeRealFiles2, AnycubicBareG5IsSkipped) {
  Toolpath p = ParseGcode(
      ";FLAVOR:Marlin\n;Generated with Cura_SteamEngine main\nM82 ;absolute extrusion mode\nG21 ;metric values\n"
      "G28 X0 Y0 ;move X/Y to min endstops\nG28 Z0 ;move Z to min endstops\nG1 Z15.0 F100\nG92 E0\n"
      "G1 F200 E3 ;extrude 3mm of feed stock\nG92 E0\nG1 F100\nG0 Y20 F100\nM117 Printing...\nG5\n"
      "G92 E0\nG1 F2400 E-6\n;LAYER_COUNT:1\n;LAYER:0\nG0 X10 Y20 Z0.2\nG1 F2400 E0\nG1 F1200 X30 E1\n",
      "i3mega.gcode");
  EXPECT_EQ(p.skipped_commands.at("G5"), 1u);
  EXPECT_NEAR(p.BeadFilamentLength(true), 1 * kMm, 1e-12);
  Toolpath curve = ParseGcode("G1 F600\nG5 I0 J3 P0 Q-3 X2 Y2\n", "b.gcode");
  EXPECT_EQ(curve.skipped_commands.count("G5"), 0u);
  EXPECT_NEAR(curve.segments.back().end_m.x(), 2 * kMm, 1e-15);
}

// FullControl (and robot slicers) write spirals and non-planar paths whose Z rises on
// every move, without layer comments or a layer height: a real ripple vase's spiral
// ("G1 F250 X51.5594 Y25.0114 Z0.291564 E0.418934" on) stands on its primer line, but a
// design that spirals from its first move had no height for any bead: every bead was
// skipped and the printed part was empty, silently. A rising bead with no height known
// now lies on the turn below it (the highest earlier bead within half a millimetre in the
// bed plane, not the same turn's), the first turn on the bed.
TEST(GcodeRealFiles2, SpiralFromTheFirstMoveStandsOnTheTurnBelow) {
  std::ostringstream g;
  g << ";GCode created with FullControl\nM83 ; relative extrusion\nG0 F8000 X60 Y50 Z0.3\n";
  const double pitch_mm = 0.3;
  double z = 0.3;
  for (int i = 1; i <= 120; ++i) {  // three turns of 40 moves around (50, 50), radius 10 mm
    const double a = i * 2 * M_PI / 40;
    z += pitch_mm / 40;
    g << "G1 F1200 X" << 50 + 10 * std::cos(a) << " Y" << 50 + 10 * std::sin(a) << " Z" << z << " E0.05\n";
  }
  Toolpath p = ParseGcode(g.str(), "spiral.gcode");
  const std::vector<double> h = BeadLayerHeights(p);
  ASSERT_EQ(h.size(), p.segments.size());
  EXPECT_NEAR(h[1], 0.3 * kMm, 1e-9);                  // the first turn stands on the bed
  for (size_t k = 45; k < h.size(); ++k) EXPECT_NEAR(h[k], pitch_mm * kMm, 0.01 * pitch_mm * kMm);
  BeadStats stats;
  BeadMeshUpTo(p, p.Duration(), {}, &stats);
  EXPECT_EQ(stats.skipped, 0u);
  EXPECT_EQ(stats.beads, 120u);
}

}  // namespace
}  // namespace lt

// Constructs met in the third pass over real slicers' and printers' files (docs/sequences.md,
// "Real files checked, third pass"), each as a tiny excerpt in the form the file has it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "scene/gcode.h"
#include "test_util.h"

namespace lt {
namespace {

using ::testing::HasSubstr;
constexpr double kMm = 1e-3;

// A MakerBot Replicator 2's start script (a printer profile's start.gcode): it homes to
// the endstops with G162/G161, states Z with G92, homes again and recalls the stored
// home offsets (M132). G161/G162/M132 were skipped with the position unchanged, so
// "G92 Z-5" shifted every later move: the purge line was laid at Z 5.3 instead of 0.3.
TEST(GcodeRealFiles3, MakerBotHomingToEndstopsLeavesThePositionToG92AndAbsoluteMoves) {
  Toolpath p = ParseGcode(
      "M73 P0 ; enable build progress\nG162 X Y F3000 ; home XY maximum\nG161 Z F1200 ; home Z minimum\n"
      "G92 Z-5 ; set Z to -5\nG1 Z0 ; move Z to 0\nG161 Z F100 ; home Z slowly\nM132 X Y Z A B ; recall home offsets\n"
      "M135 T0 ; load right extruder offsets\nG1 X-130 Y-75 Z30 F4000 ; move to wait position off table\n"
      "G130 X20 Y20 Z20 A20 B20 ; lower stepper Vrefs while heating\nG92 A0 B0 ; zero extruders\n"
      "G1 Z0.5 ; position nozzle\nG1 X-140 Y-70 Z0.3 F1200\nG1 Y60 E25 F1200\nG1 Z0.5\n",
      "rep2.gcode");
  ASSERT_FALSE(p.segments.empty());
  const ToolpathSegment* purge = nullptr;
  for (const ToolpathSegment& s : p.segments) {
    if (s.LaysBead()) purge = &s;
  }
  ASSERT_NE(purge, nullptr);
  EXPECT_NEAR(purge->start_m.z(), 0.3 * kMm, 1e-12);  // was 5.3 mm: G92 Z-5 shifted the frame
  EXPECT_NEAR(purge->end_m.y(), 60 * kMm, 1e-12);
  EXPECT_NEAR(p.segments.back().end_m.z(), 0.5 * kMm, 1e-12);
  // One warning per command, at its first line, counted.
  ASSERT_EQ(p.warnings.size(), 3u);
  EXPECT_EQ(p.warnings[0].line, 2);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("G162 homes X Y to the endstops"));
  EXPECT_EQ(p.warnings[1].line, 3);
  EXPECT_EQ(p.warnings[1].count, 2);
  EXPECT_THAT(p.warnings[1].text, HasSubstr("Z stays unknown until G92 or an absolute move"));
  EXPECT_THAT(p.warnings[2].text, HasSubstr("M132 recalls the home offsets of X Y Z"));

  // A Thing-O-Matic (Skeinforge's start.txt): Z homed to its maximum, which G92 names 80.
  // The first move went to Z -70 (80 mm below what the file says).
  Toolpath tom = ParseGcode(
      "G21\nG90\nG162 Z F500 (home Z axis maximum)\nG161 X Y F2500 (home XY axes minimum)\n"
      "G92 Z80 ( ---=== Set Z axis maximum ===--- )\nG92 X-57.5 Y-57 (set zero for X and Y)\n"
      "G1 X52.0 Y-57.0 Z10.0 F3300.0 (move to waiting position)\nG1 X-9.28 Y-9.28 Z5.2 F1440.0\n",
      "tom.gcode");
  EXPECT_NEAR(tom.segments.back().end_m.x(), -9.28 * kMm, 1e-12);
  EXPECT_NEAR(tom.segments.back().end_m.y(), -9.28 * kMm, 1e-12);
  EXPECT_NEAR(tom.segments.back().end_m.z(), 5.2 * kMm, 1e-12);

  // G92 makes the axis known there: a relative move goes on from it (it was built from
  // the last place known before the homing, Z -79.7 here, and warned).
  Toolpath rel = ParseGcode("G1 X5 Y5 Z1 F600\nG162 Z\nG92 Z80\nG91\nG1 Z-79.7\nG90\nG1 X10 Y10 E1\n", "rel.gcode");
  EXPECT_NEAR(rel.segments.back().start_m.z(), 0.3 * kMm, 1e-12);
  EXPECT_NEAR(rel.segments.back().end_m.z(), 0.3 * kMm, 1e-12);
  ASSERT_EQ(rel.warnings.size(), 1u);  // the homing's only
  EXPECT_THAT(rel.warnings[0].text, HasSubstr("G162 homes Z to the endstops"));
  // A bare G92 says the nozzle is at 0 on every axis, unknown ones included.
  Toolpath bare = ParseGcode("G1 X5 Y5 Z1 F600\nG161 Z\nG92\nG91\nG1 Z0.2\nG90\nG1 X10 E1\n", "bare.gcode");
  EXPECT_NEAR(bare.segments.back().end_m.z(), 0.2 * kMm, 1e-12);
  EXPECT_EQ(bare.warnings.size(), 1u);

  // A G92 on a known axis still shifts the frame, as before.
  Toolpath known = ParseGcode("G1 X10 F600\nG92 X0\nG1 X5\n", "k.gcode");
  EXPECT_NEAR(known.segments.back().end_m.x(), 15 * kMm, 1e-12);
  EXPECT_TRUE(known.warnings.empty());
}

// Cura's Griffin flavour (Ultimaker 3, S3, S5, S7: a real Cura 4.5 file's header) states
// the material's volume but not the filament's diameter, which is 2.85 mm on every
// printer of that firmware; the beads took 1.75 mm filament's area (0.38 of the volume).
TEST(GcodeRealFiles3, GriffinFlavourIsForUltimakersFilament) {
  Toolpath p = ParseGcode(
      ";START_OF_HEADER\n;HEADER_VERSION:0.1\n;FLAVOR:Griffin\n;GENERATOR.NAME:Cura_SteamEngine\n"
      ";GENERATOR.VERSION:4.5.0\n;TARGET_MACHINE.NAME:Ultimaker 3\n;EXTRUDER_TRAIN.0.MATERIAL.VOLUME_USED:7675\n"
      ";END_OF_HEADER\nT0\nM82 ;absolute extrusion mode\nG92 E0\nM109 S210\nG0 F15000 X9 Y6 Z2\nG280\n"
      "G1 F1500 E-6.5\n;LAYER:0\nG0 X10 Y10 Z0.27\nG1 F1500 E0\nG1 X20 Y10 E0.5\n",
      "griffin.gcode");
  EXPECT_NEAR(p.filament_diameter_m, 2.85 * kMm, 1e-15);
  EXPECT_NEAR(p.BeadFilamentLength(true), 0.5 * kMm, 1e-15);
  // G280 (the firmware's prime blob at its prime position) leaves the head where the
  // firmware puts it: a relative move after it is built from the last known place, warned.
  Toolpath g280 = ParseGcode(";FLAVOR:Griffin\nG0 F15000 X9 Y6 Z2\nG280\nG91\nG0 X8.0 Z0.5\nG90\n", "g280.gcode");
  ASSERT_EQ(g280.warnings.size(), 1u);
  EXPECT_THAT(g280.warnings[0].text, HasSubstr("G0 moves relative to a position G280 (line 3) left unknown in XZ"));
  // Other flavours keep the file's (or no) diameter.
  EXPECT_EQ(ParseGcode(";FLAVOR:Marlin\nG1 X1 E1 F600\n", "m.gcode").filament_diameter_m, 0.0);
}

// MatterControl's MatterSlice states its settings as "; filamentDiameter = 1.73" and
// "; layerThickness = 0.2" (a real 2.22 file, with "; LAYER:0" and "; LAYER_HEIGHT:0.25");
// neither was read: the beads took 1.75 mm filament's area.
TEST(GcodeRealFiles3, MatterSliceHeader) {
  Toolpath p = ParseGcode(
      "; Software Leveling Applied\n; Generated with MatterSlice 2.22.04\n; filamentDiameter = 1.73\n"
      "; extrusionWidth = 0.4\n; layerThickness = 0.2\n; firstLayerThickness = 0.25\nG21\nG28\nG90\nG92 E0\nM82\n"
      "; Layer count: 10\n; LAYER:0\n; LAYER_HEIGHT:0.25\n; TYPE:SKIRT\nG1 X158.25 Y82.96 Z2.17 F12000\n"
      "G1 X159.28 Y83.69 Z2.17 E0.052 F1500\n",
      "matterslice.gcode");
  EXPECT_NEAR(p.filament_diameter_m, 1.73 * kMm, 1e-15);
  EXPECT_NEAR(p.header_layer_height_m, 0.2 * kMm, 1e-15);
  EXPECT_EQ(p.LayerCount(), 1);
  EXPECT_NEAR(p.layer_height_m.at(0), 0.25 * kMm, 1e-15);
  // Its software levelling puts the bed's measured plane into Z (layer 0 at Z 2.17 here): said once.
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 1);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("MatterControl applied its software levelling to the file"));
}

// Skeinforge 11 for a Thing-O-Matic with a DC extruder: "M101" (extruder on) ... "M103"
// (off) around moves without E; the firmware feeds at M108's speed. The toolpath laid no
// bead and said nothing; such moves are now warned (once, counted). Skeinforge's 5D
// files (M101 with E words) are not.
TEST(GcodeRealFiles3, ExtruderOnWithoutEIsWarned) {
  Toolpath p = ParseGcode(
      "G21\nG90\nM108 S255\nM103\n(<layer> 2.6 )\nG1 X50.6 Y-29.67 Z2.6 F1920.0\nM101\n"
      "G1 X-17.4 Y13.53 Z2.6 F288.0\nG1 X-11.6 Y13.53 Z2.6 F288.0\nM103\nG1 X0 Y0 Z2.6 F1920.0\n",
      "tom.gcode");
  EXPECT_EQ(p.BeadFilamentLength(false), 0.0);
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 8);
  EXPECT_EQ(p.warnings[0].count, 2);  // the travel after M103 is not counted
  EXPECT_THAT(p.warnings[0].text, HasSubstr("moves without E while M101 (line 7) has the extruder on"));
  // Simplify3D's files for such firmware keep M101/M103 around moves with E (a real
  // excerpt's "G1 E-1.0000 F2400 / M103 / ... / M101"); a move without E among them is
  // no sign of the form.
  Toolpath five_d = ParseGcode(
      "G92 E0.0000\nG1 E-1.0000 F2400\nM103\n; feature outer perimeter\nM101\nG1 E0 F1800\n"
      "G1 X1 Y1 F600 E0.4\nG1 X2 Y1\nG1 X3 Y1 E0.8\nM103\n",
      "5d.gcode");
  EXPECT_TRUE(five_d.warnings.empty());
  // The file's E words may come after its first move without E (a travel first), or on
  // arcs only: it is still of the 5D form.
  EXPECT_TRUE(ParseGcode("M101\nG1 X10 Y10 F600\nG1 X30 Y10 E1\nM103\n", "late.gcode").warnings.empty());
  EXPECT_TRUE(ParseGcode("M101\nG1 X10 Y10 F600\nG2 X30 Y10 I10 J0 E1\nM103\n", "arc.gcode").warnings.empty());
}

// A CNC router's file (in a G-code viewer's demos) sets the feed on lines of their own,
// RS-274's form: "F4000" then "G01 Z-12.100", "F12000" then "G02 ...". Such a line was read
// as the last G0-G3 again: after a G02 it was "G2 needs I/J (centre offset) or R
// (radius)", and the file could not be read; before any motion it was "expected a command".
TEST(GcodeRealFiles3, FeedAloneOnItsLineSetsTheFeed) {
  Toolpath p = ParseGcode(
      "T1\nG43 H1\nM03 S18000\nG00 X176.604 Y554.890\nG00 Z10.000 \nF4000\nG01 Z-12.100\nF12000\n"
      "G02 X183.675 Y561.961 I3.536 J3.536\nG02 X176.604 Y554.890 I-3.536 J-3.536\nF4000\nG00 Z20.000 \nM05\nM30\n",
      "router.gcode");
  ASSERT_EQ(p.segments.size(), 6u);
  EXPECT_NEAR(p.segments[2].feed_m_s, 4000 / 60.0 * kMm, 1e-12);  // G01 Z-12.1 at F4000
  const ToolpathSegment& arc = p.segments[3];
  EXPECT_TRUE(arc.arc);
  EXPECT_NEAR(arc.Duration(), M_PI * 5.0 / (12000 / 60.0), 1e-6);  // half a circle of radius 5 at F12000
  EXPECT_NEAR(p.segments.back().end_m.z(), 20 * kMm, 1e-12);
  EXPECT_TRUE(p.warnings.empty());
  // Mach3's header: F before any motion command.
  Toolpath mach3 = ParseGcode("G21\nF140 ;(Initialize feed rate)\nG01 X10\n", "mach3.gcode");
  EXPECT_NEAR(mach3.segments.back().feed_m_s, 140 / 60.0 * kMm, 1e-12);
}

// A 5-axis printer's file turns rotary axes A, B, C while E extrudes. The reader takes A
// and B as extruders (Mach3's flavours, MakerBot's second extruder): such a file is
// refused at its first line with both, and the refusal now says why.
TEST(GcodeRealFiles3, RotaryAxesBesideEAreRefusedSayingWhy) {
  EXPECT_THAT(test::ErrorOf([] { ParseGcode("G1 X10 Y0 Z1 A30 E0.5 F600\n", "5axis.gcode"); }),
              HasSubstr("5axis.gcode:1: both E and A: one extruder axis per move (A and B are read as extruders, as "
                        "the Mach3 and Machinekit flavours and MakerBot's second extruder use them; rotary A/B axes of "
                        "a 5-axis printer are not modelled)"));
}

}  // namespace
}  // namespace lt

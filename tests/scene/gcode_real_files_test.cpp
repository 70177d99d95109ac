// Constructs met in real slicers' files (docs/sequences.md, "Real files checked"), each
// as a tiny hand-written excerpt in the form the file has it: lines that stopped a real
// file from loading, or were read wrongly, before the reader knew them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "scene/gcode.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using ::testing::HasSubstr;
constexpr double kMm = 1e-3;

// Bambu Studio's X1 Carbon start script wipes the nozzle below the bed's surface: it
// pushes the soft endstops' state with a bare "M221 S", turns the Z endstop off, wipes,
// and pops the state with "M221 R"; it homes Z with "G28 Z P0 T300" (low precision,
// a nozzle of up to 300 degrees permitted). Each of these lines was an error ("M221 S
// (flow percentage) must be >= 0", "M221 takes no parameter R", "one command per line:
// found T after the command"), so no Bambu Studio file for an X1 or P1 could be read.
TEST(GcodeRealFiles, BambuX1StartScriptSoftEndstopsAndLowPrecisionHoming) {
  Toolpath p = ParseGcode(
      "G90\nM83\nG28 X\nG1 X135 Y253 Z5 F20000\n"
      "G28 Z P0 T300; home z with low precision,permit 300deg temperature\n"
      "G29.2 S0 ; turn off ABL\nG0 Z5 F20000\n"
      "M221 S; push soft endstop status\nM221 Z0 ;turn off Z axis endstop\n"
      "G0 X125 Y259.5 Z-1.01\nG0 X131 F211\n"
      "M221 R; pop softend status\nG1 Z10 F1200\n"
      "G1 X128 Y128 Z0.2 F20000\nG1 X138 E1 F1200\n",
      "x1c.gcode");
  ASSERT_EQ(p.segments.size(), 8u);
  EXPECT_EQ(p.segments[1].gcode, 28);  // G28 Z: Z alone homes, from 5 mm
  EXPECT_NEAR(p.segments[1].start_m.z(), 5 * kMm, 1e-12);
  EXPECT_NEAR(p.segments[1].end_m.z(), 0.0, 1e-12);
  EXPECT_NEAR(p.segments[1].end_m.x(), 135 * kMm, 1e-12);
  EXPECT_NEAR(p.segments[3].end_m.z(), -1.01 * kMm, 1e-12);  // the wipe below the surface
  // The flow percentage is untouched: the bead feeds the 1 mm the file says.
  EXPECT_NEAR(p.segments.back().extruded_m, 1 * kMm, 1e-12);
  EXPECT_EQ(p.skipped_commands.at("M221"), 3u);
  EXPECT_EQ(p.skipped_commands.count("T300"), 0u);
  // A flow percentage that is one is still read, and a bad one is still an error.
  Toolpath flow = ParseGcode("M83\nM221 S50\nG1 X10 E1 F600\n", "flow.gcode");
  EXPECT_NEAR(flow.segments.back().extruded_m, 0.5 * kMm, 1e-12);
  EXPECT_THAT(ErrorOf([] { ParseGcode("M221 S-5\n", "flow.gcode"); }),
              HasSubstr("flow.gcode:1: M221 S (flow percentage) must be >= 0"));
}

// Cura's "RepRap (Volumetric)" flavour, written ";FLAVOR:Marlin(Volumetric)" (a real Cura
// 4.13.1 file's header: ";Filament used: 4615.03mm3"): E is a volume in mm^3, as
// CuraEngine documents the flavour, without M200; retraction is G10/G11. It was read as
// millimetres of filament: 2.4 times the volume for 1.75 mm filament. Held as lengths of
// Marlin's nominal 1.75 mm filament, as its volumetric mode assumes without M200 D.
TEST(GcodeRealFiles, CuraMarlinVolumetricFlavourExtrudesVolumes) {
  Toolpath p = ParseGcode(
      ";FLAVOR:Marlin(Volumetric)\n;TIME:64\n;Filament used: 18mm3\n;Layer height: 0.4\n"
      ";Generated with Cura_SteamEngine 4.13.1\nM82 ;absolute extrusion mode\nG28 ;Home\n"
      ";LAYER_COUNT:1\n;LAYER:0\nG0 X10 Y10 Z0.4 F3000\nG1 X20 Y10 E6 F1200\nG1 X20 Y20 E18\n"
      "G10\nG0 X30 Y30\nG11\n;TIME_ELAPSED:64.979067\n",
      "volumetric.gcode");
  const double area_mm2 = M_PI * 0.25 * 1.75 * 1.75;
  double bead_e = 0;
  for (const ToolpathSegment& s : p.segments) {
    if (s.LaysBead()) bead_e += s.extruded_m;
  }
  EXPECT_NEAR(bead_e, 18 / area_mm2 * kMm, 1e-15);  // the header's 18 mm^3
  EXPECT_NEAR(p.filament_diameter_m, 1.75 * kMm, 1e-15);
  EXPECT_NEAR(p.ExtrudedLength(), 18 / area_mm2 * kMm, 1e-15);  // G10/G11 cancel
}

// PrusaSlicer's start scripts for the MK4, XL and Core One wait for the bed's heat to
// soak in with "G29 G ; absorb heat"; OctoPrint's bed level visualizer has the mesh
// reported with "G29 T" (here in a Prusa XL's start script). Both were errors ("G
// without a number": a bare G was taken for the line's next command; "one command per
// line: found T after the command"), so no file sliced for these printers could be read.
// Neither probes: skipped; the probing around them is warned as before.
TEST(GcodeRealFiles, PrusaAbsorbHeatAndMeshReport) {
  Toolpath p = ParseGcode(
      "M140 S60 ; set bed temp\nG28 XY\nT0 S1 L0 D0\nM84 E ; turn off E motor\nG28 Z\n"
      "G0 Z5 ; add Z clearance\nM190 S60 ; wait for bed temp\nG29 G ; absorb heat\n"
      "G1 X32.0999 Y-6.90006 Z5 F24000\nG29 P1 ; invalidate mbl & probe print area\n"
      "G29 P3.2 ; interpolate mbl probes\nG29 A ; activate mbl\nG29 T\n"
      "G1 X40 Y10 Z10 F720\n",
      "xl.gcode");
  EXPECT_EQ(p.skipped_commands.at("G29"), 4u);  // G, P3.2, A, T
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 10);  // G29 P1 probes
  EXPECT_EQ(p.warnings[0].count, 1);
  EXPECT_NEAR(p.segments.back().end_m.x(), 40 * kMm, 1e-12);
  // A G without a number is still no command of its own.
  EXPECT_THAT(ErrorOf([] { ParseGcode("G21 G\n", "g.gcode"); }), HasSubstr("g.gcode:1: G without a number"));
}

// KISSlicer 1.1 starts a raft's layers with "; BEGIN_LAYER_RAFT z=0.50" (no
// z_thickness), then the object's with "; BEGIN_LAYER_OBJECT z=1.00". Only the object's
// were layers: a real file's two raft layers (59 % of its filament) were outside any
// layer, and it had 12 layers where it prints 14.
TEST(GcodeRealFiles, KisslicerRaftLayersAreLayers) {
  Toolpath p = ParseGcode(
      "; KISSlicer - FREE\n; version 1.1.0.5\nG21 ; Set to metric\nM82 ; Absolute Extruder\nG90\n"
      "; Reset extruder pos\nG92 E0\n; BEGIN_LAYER_RAFT z=0.50\n; 'Raft', 0.8 [feed mm/s], 20.0 [head mm/s]\n"
      "G1 F9000\nG1 X11.39 Y-1.49 Z0.5 E0\nG1 F1200\nG1 E1\nG1 X8.05 Y1.85 E1.197\nG1 F210\n"
      "G1 X8.05 Y1.85 Z0.75 E1.197\n; END_LAYER_RAFT z=0.50\nG92 E0\n; BEGIN_LAYER_RAFT z=0.75\n"
      "G1 F9000\nG1 X11.39 Y1.49 Z0.75 E0\nG1 F2400\nG1 X8.05 Y-1.85 E0.0985\nG1 F210\n"
      "G1 X8.05 Y-1.85 Z1 E0.0985\n; END_LAYER_RAFT z=0.75\nG92 E0\n; BEGIN_LAYER_OBJECT z=1.00\n"
      "; 'Crown', 0.1 [feed mm/s], 9.1 [head mm/s]\nG1 F9000\nG1 X-9.72 Y-9.72 Z1 E0\nG1 F546.9\n"
      "G1 X-9.74 Y9.43 E0.2955\n; END_LAYER_OBJECT z=1.00\n",
      "thinbox.gcode");
  EXPECT_EQ(p.LayerCount(), 3);
  int beads = 0;
  for (const ToolpathSegment& s : p.segments) {
    if (!s.LaysBead()) continue;
    ++beads;
    EXPECT_NE(s.layer, ToolpathSegment::kNoLayer) << s.line;
    EXPECT_EQ(s.layer, s.end_m.z() < 0.6 * kMm ? 0 : s.end_m.z() < 0.8 * kMm ? 1 : 2) << s.line;
  }
  EXPECT_EQ(beads, 3);
}

// Skeinforge writes its settings as parenthesised comments that hold parentheses:
// "(<setting> dimension Filament_Diameter_(mm): 1.82 </setting>)". The comment ended at
// the first ')', and ": 1.82 </setting>)" was "expected a command (G, M or T)": no
// Skeinforge file (MakerBot's sample files among them) could be read. A '(' inside a
// comment now nests, as ReplicatorG, the host these files were written for, read them.
TEST(GcodeRealFiles, SkeinforgeNestedParenthesesInComments) {
  Toolpath p = ParseGcode(
      "(<format> skeinforge gcode </format>)\n(<layerThickness> 0.27 </layerThickness>)\n"
      "(<setting> dimension Filament_Diameter_(mm): 1.82 </setting>)\n"
      "(<setting> dimension Extruder_Retraction_Speed_(mm/s): 20.0 </setting>)\n"
      "(<layer> 0.675 )\n(<rotation> (6.12323399574e-17+1j) )\n(<loop> outer )\n"
      "G1 X-9.22 Y-9.4 Z0.68 F3300.0\nM101\nG1 X-0.5 Y-9.4 Z0.68 F2400.0 E0.426\n"
      "G1 X-0.5 (a (nested) note) Y-0.5 Z0.68 F2400.0 E0.861\nM103\n(</loop>)\n(</layer>)\n",
      "skeinforge.gcode");
  ASSERT_EQ(p.segments.size(), 3u);
  EXPECT_NEAR(p.segments[2].end_m.y(), -0.5 * kMm, 1e-12);  // the words after a nested comment are read
  EXPECT_NEAR(p.ExtrudedLength(), 0.861 * kMm, 1e-12);
  EXPECT_TRUE(p.warnings.empty());
  // A '(' that never closes still runs to the end of its line, warned.
  Toolpath unclosed = ParseGcode("G1 X10 F600 (a (b) c Y5\n", "u.gcode");
  EXPECT_NEAR(unclosed.segments.back().end_m.y(), 0.0, 1e-12);
  EXPECT_EQ(unclosed.warnings.size(), 1u);
}

// The intro line of Prusa's MK3 start script as an older slicer wrote it (here in
// compas_slicer's test output): "G80" (mesh levelling: the position unknown after it),
// then "G1 Y-3.0", "G1 X60.0 E9.0": X and Y set again, Z never. The line's bead was laid
// at the last known Z without a word; it is now warned (once, counted), naming the
// probing and the Z assumed. A prime in place and beads after an absolute Z are not.
TEST(GcodeRealFiles, BeadWithAnAxisUnknownAfterProbingIsWarned) {
  Toolpath p = ParseGcode(
      "M83; extruder relative mode\nG28 ; home all axes without mesh bed level\nG80 ; mesh bed leveling\n"
      "G1 Y-3.0 F1000.0 ; go outside print area\nG92 E0 ; set filament pos to 0\nG1 E2 F300\n"
      "G1 X60.0 E9.0 F1000 ; intro line\nG1 X100 E12.5 F1000 ; intro line\nG92 E0\n"
      "G1 X10 Y10 Z0.2 F3000\nG1 X20 Y10 E1\n",
      "mk3.gcode");
  ASSERT_EQ(p.warnings.size(), 2u);  // G80's probing time, and the beads
  EXPECT_EQ(p.warnings[1].line, 7);
  EXPECT_EQ(p.warnings[1].count, 2);
  EXPECT_THAT(p.warnings[1].text, HasSubstr("G80 (line 3)"));
  EXPECT_THAT(p.warnings[1].text, HasSubstr("last known Z0"));
  EXPECT_NEAR(p.segments.back().end_m.z(), 0.2 * kMm, 1e-12);
}

// A RepRapFirmware tool changer's start.g (E3D's, as a user's configuration has it) loads
// its height map with 'G29 S1 P"heightmap.csv"' and primes each tool with 'M98
// P"prime.g"'. The quoted file name was "expected a parameter letter, got
// ""heightmap.csv""": the file could not be read. A quoted string is now a word without a
// number (G29 S1 with a file loads a map: no probing); M98 runs a macro file the reader
// does not have, so it is warned once per file, as an unknown Klipper macro is.
TEST(GcodeRealFiles, RepRapFirmwareFileNamesAndMacroCalls) {
  Toolpath p = ParseGcode(
      "M290 R0 Z0\nG10 P0 R205 S205\nM18\nT0\nM703\nT-1\nG28 ; home all axes\n"
      "T0\nM98 P\"prime.g\"\nT1\nM98 P\"prime.g\"\nT-1\nM290 R1 Z-0.15\n"
      "G29 S1 P\"heightmap.csv\" ; Use the Z offset Mesh Map on the SD card\n"
      "G29 S3 P\"a \"\"b\"\".csv\"\nG1 X10 Y10 Z0.3 F3000\n",
      "start.g");
  EXPECT_EQ(p.skipped_commands.at("G29"), 2u);
  ASSERT_EQ(p.warnings.size(), 1u);  // no probing warning: the map is loaded, not probed
  EXPECT_EQ(p.warnings[0].line, 9);
  EXPECT_EQ(p.warnings[0].count, 2);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("M98 P\"prime.g\" skipped"));
  EXPECT_NEAR(p.segments.back().end_m.z(), (0.3 - 0.15) * kMm, 1e-12);  // the babystep holds
  EXPECT_THAT(ErrorOf([] { ParseGcode("G29 S1 P\"heightmap.csv\n", "g.gcode"); }),
              HasSubstr("g.gcode:1: P has a string without its closing"));
}

}  // namespace
}  // namespace lt

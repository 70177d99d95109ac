// Constructs met in the fifth pass over real slicers' and printers' files (docs/sequences.md,
// "Real files checked, fifth pass"), each as a tiny excerpt in the form the file has it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "error_of.h"
#include "scene/gcode.h"

namespace lt {
namespace {

using ::testing::HasSubstr;
constexpr double kMm = 1e-3;

// MakerBot's G-code (GPX, ReplicatorG) changes tools with "M135 T1" (also "M6 T1" and
// ReplicatorG's "M108 T1"); E is then the new tool's axis, B. M135 was skipped, so E
// stayed on A: after A3 the right extruder's "E0.5" was a 2.5 mm retraction of the left
// one, which the next B feed made up (no bead on lines 8 and 9), and back on T0 "E4" fed
// 3.5 mm where A feeds 1 mm.
TEST(GcodeRealFiles5, MakerBotToolChangeByMCodeMovesEOntoB) {
  for (const char* change : {"M135 T%", "M6 T%", "M108 T%"}) {
    auto tool = [&](char n) {
      std::string line(change);
      line[line.size() - 1] = n;
      return line + "\n";
    };
    const std::string text = "G92 X0 Y0 Z0 A0 B0\n" + tool('0') +
                             "G1 X0 Y0 Z0.2 F1200\nG1 X10 Y0 A1\nG1 X10 Y10 A2\nG1 X0 Y10 A3\n" + tool('1') +
                             "G1 X0 Y0 E0.5\nG1 X10 Y0 B1.5\n" + tool('0') + "G1 X10 Y10 E4\n";
    Toolpath p = ParseGcode(text, "dual.gcode");
    ASSERT_EQ(p.segments.size(), 7u) << change;
    const double fed_mm[7] = {0, 1, 1, 1, 0.5, 1, 1};  // the moves from line 3 on
    for (int k = 0; k < 7; ++k) {
      EXPECT_NEAR(p.segments[size_t(k)].extruded_m / kMm, fed_mm[k], 1e-9) << change << ", line " << p.segments[size_t(k)].line;
      EXPECT_NEAR(p.segments[size_t(k)].laid_m / kMm, fed_mm[k], 1e-9) << change << ", line " << p.segments[size_t(k)].line;
    }
  }
  // Without T they select nothing (Skeinforge's "M108 S255" is a speed, RepRapFirmware's
  // "M135 S100" a PID interval): E stays on A.
  Toolpath p = ParseGcode(
      "G92 A0 B0\nG1 X0 Y0 Z0.2 F1200\nG1 X10 Y0 A1\nG1 X10 Y10 A2\nM108 S255\nM135 S100\nG1 X0 Y10 E3\n", "t.gcode");
  EXPECT_NEAR(p.BeadFilamentLength(false) / kMm, 3, 1e-9);
}

// A feed in place (no X/Y motion) that is no prime of an earlier retraction is a blob:
// Cura 5.0's clay-style cube starts its layer with "G1 X82.0468 Y137.2064 E10" at the
// travel's end point. It lays no bead (a bead needs a path; the blob's shape is the
// material's), which left 10 of the file's 140 mm unaccounted for, silently. It is now
// counted (Toolpath::BlobFilamentLength) and, within a layer, warned with the amount;
// a prime after a retraction stays no blob.
TEST(GcodeRealFiles5, BlobFedInPlaceIsCountedAndWarned) {
  const std::string text =
      ";FLAVOR:Marlin\n;Layer height: 1\nM82\nG92 E0\n;LAYER:0\n"
      "G0 F600 X82.0468 Y137.2064 Z1\nG1 X82.0468 Y137.2064 E10\nG1 X92.0468 Y137.2064 E12\n"
      "G1 E8 F1800\nG0 X100 Y100\nG1 E12 F1800\nG1 X110 Y100 E13\n";
  Toolpath p = ParseGcode(text, "clay.gcode");
  EXPECT_NEAR(p.BeadFilamentLength(true) / kMm, 3, 1e-9);
  EXPECT_NEAR(p.BlobFilamentLength(true) / kMm, 10, 1e-9);
  EXPECT_NEAR(p.ExtrudedLength() / kMm, 13, 1e-9);
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 7);
  EXPECT_EQ(p.warnings[0].count, 1);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("a blob"));
  EXPECT_THAT(p.warnings[0].text, HasSubstr("10.000 mm"));

  // A start script's prime or purge in place (outside the layers) is counted, not warned.
  Toolpath start = ParseGcode("G92 E0\nG1 Z0.3 F600\nG1 E5 F300\n;LAYER:0\nG1 X10 Y0 E6\n", "start.gcode");
  EXPECT_NEAR(start.BlobFilamentLength(false) / kMm, 5, 1e-9);
  EXPECT_NEAR(start.BlobFilamentLength(true) / kMm, 0, 1e-12);
  EXPECT_TRUE(start.warnings.empty());

  // A printer with two nozzles primes the new tool in place after a change (Cura 4.9.1
  // for a QIDI i-Fast: "G1 F1200 E89.20347" retracts the old tool 8.5 mm, then "G92 E0",
  // "T0", "G92 E0", "G1 F1200 E8.5"): the new tool's nozzle is refilled, no blob, though
  // the reader does not know how far that tool was retracted when it was parked.
  Toolpath dual = ParseGcode(
      ";LAYER:0\nG1 Z0.3 F600\nG1 X10 Y0 E5 F1350\nG1 F1200 E-3.5\nG92 E0\nT1\nG92 E0\nG0 X20 Y0\n"
      "G1 F1200 E8.5\nG1 X30 Y0 E9.5\nG1 F1200 E1\nG92 E0\nT0\nG92 E0\nG1 F1200 E8.5\nG1 X30 Y10 E10\n",
      "dual.gcode");
  EXPECT_NEAR(dual.BlobFilamentLength(false) / kMm, 0, 1e-12);
  EXPECT_NEAR(dual.BeadFilamentLength(false) / kMm, 5 + 1 + 1.5, 1e-9);
  EXPECT_TRUE(dual.warnings.empty());

  // Slic3r's absolute E: a retraction to "E1.42602" from "E2.42602", "G92 E0" and the
  // prime "E1.00000" make up each other up to the rounding of the differences (4e-16
  // mm were laid: a blob of nothing, warned as "0.000 mm").
  Toolpath slic3r = ParseGcode(
      "G1 Z0.2 F600\nG1 X8.621 Y8.621 E2.07082\nG1 X-8.537 Y8.621 E2.42602\nG1 F1800.000 E1.42602\nG92 E0\n"
      "G1 Z0.400 F7800.000\nG1 X8.621 Y8.621\nG1 F1800.000 E1.00000\nG1 X-8.621 Y8.621 F1800.000 E1.35694\n",
      "slic3r.gcode");
  for (const ToolpathSegment& s : slic3r.segments) EXPECT_FALSE(s.LaysBlob()) << "line " << s.line;
  EXPECT_TRUE(slic3r.warnings.empty());

  // Relative E (M83): a wipe retracting in three rounded pieces, the rest of the
  // retraction, then the prime of the whole in one word: 0.79999 mm drawn back, 0.8 fed
  // (a blob of 1e-5 mm, warned as "0.000 mm", before the rounding of several words was
  // allowed for). A prime with a deliberate extra (0.05 mm) still lays a blob.
  const std::string wipe =
      "M83\n;LAYER_CHANGE\n;Z:0.2\nG1 Z0.2 F600\nG1 X10 Y10 F9000\nG1 X30 Y10 E0.9 F1200\n"
      "G1 X30 Y25 E-0.12345 F2400\nG1 X30 Y20 E-0.12345\nG1 X30 Y15 E-0.12345\nG1 E-0.42964 F2100\n"
      "G1 X40 Y40 F9000\nG1 E0.8 F2100\nG1 X50 Y40 E0.4 F1200\n";
  Toolpath wiped = ParseGcode(wipe, "wipe.gcode");
  EXPECT_EQ(wiped.BlobFilamentLength(false), 0);
  EXPECT_TRUE(wiped.warnings.empty());
  Toolpath extra = ParseGcode(wipe.substr(0, wipe.find("G1 E0.8")) + "G1 E0.85 F2100\n", "extra.gcode");
  EXPECT_NEAR(extra.BlobFilamentLength(true) / kMm, 0.05001, 1e-9);
}

// QIDI Print (Cura 4.9.1) for the two-nozzle QIDI i-Fast primes both nozzles in its start
// script on their own axes, MakerBot's way ("T1", "G1 X330 B19", "T0", "G1 X5 A19",
// "G92 A0 B0"), and prints with E. Since A and B in a file printing with E were taken as
// extra axes (a thread-laying ring's A), the two 19 mm purge lines were ignored, with a
// warning that "A and B are no extruders here". A and B named each only under its own
// tool keep the MakerBot reading: extruder axes beside E.
TEST(GcodeRealFiles5, APrimeUnderT0AndBPrimeUnderT1AreExtruders) {
  const std::string text =
      ";FLAVOR:Marlin\nM82 ;absolute extrusion mode\nG92 A0 B0\nG28\nG1 X0 Y0 Z50 F3600\nG92 E0\nG92 A0 B0\n"
      "G0 X0 Y4 Z0.3 F3600\nT1\nG1 X330 B19 F2400\nT0\nG1 X330 Y5 F3600\nG1 X5 A19 F2400\nG92 A0 B0\n"
      "G0 X5 F2400\nG92 E0\nG1 F1800 E0\nG1 F2400 X147.594 Y108.322 E11.41078\nG92 E0\n;LAYER:0\n"
      "G0 F4200 X150 Y110 Z0.3\nG1 F1350 X158.278 Y133.049 E1\nG1 X173.048 Y118.844 E2\n";
  Toolpath p = ParseGcode(text, "qidi.gcode");
  EXPECT_NEAR(p.BeadFilamentLength(false) / kMm, 19 + 19 + 11.41078 + 2, 1e-9);  // was 13.41078
  EXPECT_NEAR(p.BeadFilamentLength(true) / kMm, 2, 1e-9);
  EXPECT_TRUE(p.warnings.empty());
  // An A turning under T1 (or a ring's A with no B) is still no extruder in such a file.
  Toolpath ring = ParseGcode(
      "T1\nG92 A0 B0\nG1 X10 Y0 Z0.3 B1 F600\nG1 X20 Y0 A30\nG1 X30 Y0 E1\nG1 X40 Y0 E2\nG1 X50 Y0 E3\n", "r.gcode");
  EXPECT_NEAR(ring.BeadFilamentLength(false) / kMm, 3, 1e-9);
  ASSERT_EQ(ring.warnings.size(), 1u);
  EXPECT_THAT(ring.warnings[0].text, HasSubstr("A and B are no extruders here"));
}

// Legacy Cura (15.04) states the layer height in its settings line (a FABtotum file:
// ";Basic settings: Layer height: 0.15 Walls: 2 Fill: 10"), which was not read (0: no
// header height for the beads that need one, a spiral's).
TEST(GcodeRealFiles5, LegacyCuraBasicSettingsGiveTheLayerHeight) {
  Toolpath p = ParseGcode(
      ";Sliced at: Thu 25-05-2017 10:25:01\n;Basic settings: Layer height: 0.15 Walls: 2 Fill: 10\n"
      ";Print time: 37 minutes\n;Filament used: 1.707m 5.0g\nG90\n;LAYER:0\nG0 F12000 X84.858 Y27.177 Z0.150\n"
      "G1 F2400 X87.164 Y25.363 E0.07319\n",
      "fabtotum.gcode");
  EXPECT_NEAR(p.header_layer_height_m / kMm, 0.15, 1e-12);
  EXPECT_THAT(test::ErrorOf([] { ParseGcode(";Basic settings: Layer height: thin Walls: 2\n", "bad.gcode"); }),
              HasSubstr("bad.gcode:1"));
}

// BCN3D's Sigma (an IDEX printer) prints two copies with "M605 S2 X105.0" (Marlin's
// DUAL_X_CARRIAGE duplication; S3 mirrors, BCN3D's firmware mirrors with S4), in the start
// script Cura 2.7.0 and Sigma ProGen write. M605 was skipped silently: the toolpath holds
// the first carriage's moves only, and half the printed parts were missing without a word.
TEST(GcodeRealFiles5, DualCarriageDuplicationIsWarned) {
  const std::string text =
      "G28 X0 Y0\nG1 Z5 F200\nT0\nG92 E0\nG1 E20 F50\nG92 E0\nG1 F2400 E-8\n"
      "G90\nM605 S2 X105.0\t\t;set dual carriage mode, Duplication\nG92 E-8\n"
      ";LAYER:0\nG0 F3600 X20 Y20 Z0.2\nG1 F1500 E0\nG1 F1800 X40 Y20 E0.7\nM605 S4 X105.0\n";
  Toolpath p = ParseGcode(text, "sigma.gcode");
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 9);
  EXPECT_EQ(p.warnings[0].count, 2);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("M605 S2"));
  EXPECT_THAT(p.warnings[0].text, HasSubstr("not in the toolpath"));
  // Full control (S0) and auto-park (S1) print with one carriage at a time: no warning.
  EXPECT_TRUE(ParseGcode("M605 S1\nG1 X10 Y0 Z0.2 E1 F600\nM605 S0\n", "idex.gcode").warnings.empty());
}

}  // namespace
}  // namespace lt

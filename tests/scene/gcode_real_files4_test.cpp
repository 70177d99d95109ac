// Constructs met in the fourth pass over real slicers' and printers' files (docs/sequences.md,
// "Real files checked, fourth pass"), each as a tiny excerpt in the form the file has it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "scene/gcode.h"
#include "test_util.h"

namespace lt {
namespace {

using ::testing::HasSubstr;
constexpr double kMm = 1e-3;

double BeadFilamentMm(const Toolpath& p) {
  double sum = 0;
  for (const ToolpathSegment& s : p.segments) {
    if (s.LaysBead()) sum += s.laid_m;
  }
  return sum / kMm;
}

// Cura 5.4 for a printer whose A axis turns a ring that lays a thread (a research
// printer's start script): "G92 A90" and "G0 F5000 A14.891" turn the ring, E prints.
// A was read as an extruder: the ring's turn was a 75.1 mm retraction, which the purge
// lines' 30 mm of E then "made up", so they laid nothing (beads 0 mm, net -87.6 mm).
TEST(GcodeRealFiles4, AAxisOfAFileThatPrintsWithEIsNoExtruder) {
  const std::string text =
      "M82 ; absolute extrusion mode\nG92 E0 ; Reset Extruder\nG28 X Y Z\n"
      "G92 A90 ; Assume the ring has been manually homed, set its position to 90\n"
      "G0 F5000 X55.0 ; Move head out of the way of the carrier\n"
      "G0 F5000 A14.891 ; Move ring to initial thread position\n"
      "G1 Z2.0 F3000\nG1 X0.1 Y20 Z0.3 F5000.0\nG1 X0.1 Y200.0 Z0.3 F1500.0 E15\n"
      "G1 X0.4 Y200.0 Z0.3 F5000.0\nG1 X0.4 Y20 Z0.3 F1500.0 E30\nG92 E0\nG1 F1500 E-6.5\n";
  Toolpath p = ParseGcode(text, "ring.gcode");
  EXPECT_NEAR(BeadFilamentMm(p), 30.0, 1e-9);  // was 0
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 4);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("axis A ignored"));
  EXPECT_THAT(p.warnings[0].text, HasSubstr("A and B are no extruders here"));
  // The ring's turn is no move of the nozzle (it was a retraction taking 0.9 s).
  for (const ToolpathSegment& s : p.segments) EXPECT_GE(s.extruded_m, -6.5 * kMm - 1e-12);

  // A file that prints with A (Cura's Mach3 flavour, MakerBot) keeps A as its extruder,
  // even beside an E in a start script's purge; a start script's "G92 A0 B0" names no
  // moving axis (a Replicator 2's purge with E stays as it was, without a warning).
  Toolpath mach3 = ParseGcode("G1 X0 Y10 Z0.3 E5 F600\nG92 A0\nG1 X10 Y10 A1\nG1 X10 Y20 A2\nG1 X0 Y20 A3\n", "mach3.gcode");
  EXPECT_NEAR(BeadFilamentMm(mach3), 8.0, 1e-9);
  ASSERT_EQ(mach3.warnings.size(), 1u);  // E goes onto A's position (MakerBot's reading), said
  EXPECT_EQ(mach3.warnings[0].line, 1);
  EXPECT_THAT(mach3.warnings[0].text, HasSubstr("E read as the active tool's axis"));
  Toolpath rep2 = ParseGcode("G92 A0 B0\nG1 X-140 Y-70 Z0.3 F1200\nG1 Y60 E25 F1200\n", "rep2.gcode");
  EXPECT_NEAR(BeadFilamentMm(rep2), 25.0, 1e-9);
  EXPECT_TRUE(rep2.warnings.empty());
  // A rotary A turning while the line extrudes with E is still refused, naming the line
  // (before the file's end shows that it prints with E).
  const std::string error =
      test::ErrorOf([] { ParseGcode("G1 X10 Y0 Z0.2 E1 F600\nG1 X20 E2\nG1 A30\nG1 X30 Y5 A40 E3\n", "5ax.gcode"); });
  EXPECT_THAT(error, HasSubstr("5ax.gcode:4"));
  EXPECT_THAT(error, HasSubstr("both E and A"));
}


// IceSL (2021, for an Anycubic Mega Zero): its settings are "; name : <tab>value" lines
// and its layers "; <layer 0>" ... "; </layer>". Neither was read: the filament
// diameter stayed the default (a 2.85 mm file's beads took 1.75 mm filament's area,
// 0.38 of the volume) and the layers came from the heights, which put the start
// script's purge line (Z 0.3) into layer 0 beside the part's first layer (Z 0.28).
TEST(GcodeRealFiles4, IceSLSettingsAndLayerComments) {
  const std::string text =
      "G92 E0\nG1 X20 Y10 Z0.3 F5000.0 ; move to start-line position\n"
      "G1 X150 Y10 Z0.3 F1500.0 E15 ; draw 1st line\nG92 E0 ; reset extruder\n"
      "; <IceSL Dec 20 2021 17:10:40>\n; filament_diameter_mm_0 : \t2.85\n; nozzle_diameter_mm_0 : \t0.4\n"
      "; z_layer_height_mm : \t0.28\nM106 S0\n; <layer 0>\nG1 Z0.280\n; retract\nG1 F1800 E-7.000000\n"
      "G0 F7200 X109.200 Y106.600 Z0.280000\n; prime\nG1 F1800 E0.000000\nG1 F1200 X108.776 Y106.639 E0.019826\n"
      "G1 X108.623 Y106.666 E0.027061\n; retract\nG1 F1800 E-6.972939\nG92 E0\n; </layer>\n; <layer 1>\n"
      "G1 Z0.560\n; prime\nG1 F1800 E7.000000\nG0 F7200 X109.200 Y110.800 Z0.560000\n"
      "G1 F2100 X110.800 Y110.800 E7.074503\n; retract\nG1 F1800 E0.074503\nG92 E0\n; </layer>\n";
  Toolpath p = ParseGcode(text, "icesl.gcode");
  EXPECT_NEAR(p.filament_diameter_m, 2.85 * kMm, 1e-12);     // was 0: the default 1.75 mm
  EXPECT_NEAR(p.header_layer_height_m, 0.28 * kMm, 1e-12);  // was 0
  EXPECT_FALSE(p.layers_from_z);
  EXPECT_EQ(p.LayerCount(), 2);
  for (const ToolpathSegment& s : p.segments) {
    if (!s.LaysBead()) continue;
    // The purge line is outside the layers (it was in layer 0), the part's beads in theirs.
    const int expected = s.start_m.z() > 0.5 * kMm ? 1 : s.start_m.z() > 0.29 * kMm ? ToolpathSegment::kNoLayer : 0;
    EXPECT_EQ(s.layer, expected) << "bead at line " << s.line;
  }
  EXPECT_NEAR(BeadFilamentMm(p), 15 + 0.027061 + 0.074503, 1e-6);
  // Only "<layer N>" is a layer: a comment that merely starts so is a comment (it
  // refused the whole file: "comment without a number").
  for (const char* comment : {"; <layer 5 is thin>\n", "; <layer 1.5>\n", "; <layer 7\n", "; <layer >\n"}) {
    const Toolpath q = ParseGcode(comment + text, "icesl.gcode");
    EXPECT_EQ(q.LayerCount(), 2) << comment;
  }
}

// A filament-change insert (a G-code utility's template, spliced into a print at a
// layer): "M0 ; Pause" three times around heating and a purge, as Cura's Pause at
// Height writes M0 (Marlin), M25 or M226 and PrusaSlicer's colour change M600. The
// pauses were skipped without a word, though every time after them is early by as
// long as the printer waits for the user. Now one warning per command, at its first
// line, with the count; the path and times are unchanged.
TEST(GcodeRealFiles4, PausesForTheUserAreWarned) {
  const std::string text =
      "G91 ;Relative positioning\nG1 E-2 F2700 ;Retract a bit\nG1 E-2 Z0.2 F2400 ;Retract and raise Z\n"
      "G1 Z20\nG90 ;Absolute positionning\nG0 X0.5 Y0.5\nM104 S0 ;Turn-off hotend\nM0 ; Pause\n"
      "M109 S200 ; wait for nozzle temp\nM0 ; Pause\nG92 E0 ; Reset Extruder\nG1 F800 E500 ; Extrude some filament\n"
      "M0 ; Pause\nG28 ; AutoHome\nG92 E0\nG1 X5 Y7.0 Z0.3 F5000.0\nG1 X200 Y7.0 Z0.3 F1500.0 E15\n"
      "M600 ; colour change\nG1 X200 Y20 E16\n";
  Toolpath p = ParseGcode(text, "change.gcode");
  ASSERT_EQ(p.warnings.size(), 2u);
  EXPECT_EQ(p.warnings[0].line, 8);
  EXPECT_EQ(p.warnings[0].count, 3);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("M0, a stop until the user resumes"));
  EXPECT_THAT(p.warnings[0].text, HasSubstr("every time after it (the printed part's, a scan's) is early"));
  EXPECT_EQ(p.warnings[1].line, 18);
  EXPECT_THAT(p.warnings[1].text, HasSubstr("M600, a filament change"));
  EXPECT_EQ(p.skipped_commands.at("M0"), 3u);
  EXPECT_NEAR(BeadFilamentMm(p), 16.0, 1e-9);
  // Bambu Lab's pause, "M400 U1" (real files state machine_pause_gcode = M400 U1), is one
  // too; M400 alone (wait for the moves) and other commands are skipped silently as before.
  Toolpath bambu = ParseGcode("G1 X10 Y0 Z0.2 E1 F600\nM400 U1\nM400\nG1 X20 E2\n", "bambu.gcode");
  ASSERT_EQ(bambu.warnings.size(), 1u);
  EXPECT_EQ(bambu.warnings[0].line, 2);
  EXPECT_THAT(bambu.warnings[0].text, HasSubstr("M400 U1, Bambu Lab's pause"));
  EXPECT_TRUE(ParseGcode("M117 Printing\nM400\nG1 X10 Y0 Z0.2 E1 F600\n", "plain.gcode").warnings.empty());
  // Marlin's M0/M1 with a time ends by itself when the time passes: a dwell of that
  // time, warned as such (found in review: "M0 S5" was warned as a stop for the user
  // and took no time); a message's words are no time.
  Toolpath timed = ParseGcode("G1 X10 Y0 Z0.2 F600\nM0 S5 Cooling\nM1 P500\nM0 Press to resume\n", "timed.gcode");
  ASSERT_EQ(timed.warnings.size(), 3u);
  EXPECT_EQ(timed.warnings[0].line, 2);
  EXPECT_EQ(timed.warnings[0].count, 1);
  EXPECT_THAT(timed.warnings[0].text, HasSubstr("M0 with a time (Marlin: a stop that ends when the user resumes"));
  EXPECT_EQ(timed.warnings[1].line, 3);
  EXPECT_THAT(timed.warnings[1].text, HasSubstr("M1 with a time"));
  EXPECT_EQ(timed.warnings[2].line, 4);
  EXPECT_THAT(timed.warnings[2].text, HasSubstr("M0, a stop until the user resumes"));
  double dwell_s = 0;
  for (const ToolpathSegment& s : timed.segments) {
    if (s.gcode == 4) dwell_s += s.t_end_s - s.t_start_s;
  }
  EXPECT_NEAR(dwell_s, 5.5, 1e-12);
}

// A test file for Klipper's arc support lifts with "G0 Z10.0000 S0" (S: a laser's power or
// spindle speed in Marlin's laser mode and Grbl, an endstop mode in older RepRapFirmware;
// S0 is none of them, and Marlin and Klipper ignore it): it was refused at that line ("G0
// takes no parameter S"). S0 on a move is ignored; another S is still refused, saying why.
TEST(GcodeRealFiles4, SZeroOnAMoveIsIgnored) {
  Toolpath p = ParseGcode("G28 ; home\nG0 Z10.0000 S0 ; lift z\nG90\nG2 X20 Y0 I10 J0 Z20 S0 F8000\n", "arcs.gcode");
  ASSERT_FALSE(p.segments.empty());
  EXPECT_NEAR(p.segments.back().end_m.z(), 20 * kMm, 1e-12);
  EXPECT_NEAR(p.segments.back().end_m.x(), 20 * kMm, 1e-12);
  const std::string error = test::ErrorOf([] { ParseGcode("G1 X10 S1 F600\n", "rrf.gcode"); });
  EXPECT_THAT(error, HasSubstr("rrf.gcode:1: G1 S1 is not supported"));
  EXPECT_THAT(error, HasSubstr("S0, none of them, is ignored"));
}

// MakerWare (Miracle Grue 3.9.4) for a Replicator: its start script primes with E
// ("G1 X-141 Y-74 Z0.270 F1800.000 E25.000 (Extruder Prime Start)"), resets the
// extruders with "G92 A0 B0" and moves to "E0.0"; the print extrudes on A. MakerBot's
// G-code (GPX, Sailfish) reads E as the active tool's axis, A for T0: E0.0 after G92 A0
// moves nothing. Read as an axis of its own, E0.0 was a 25 mm retraction that the
// print's first 25 mm of A then made up: the first layer's beads lost 25 of 35.3 mm.
TEST(GcodeRealFiles4, EIsTheActiveToolsAxisInAFileThatPrintsWithA) {
  const std::string text =
      "G92 X152 Y75 Z0 A0 B0\nM135 T0\n"
      "G1 X105.400 Y-74.000 Z0.270 F9000.000 (Extruder Prime Dry Move)\n"
      "G1 X-141 Y-74 Z0.270 F1800.000 E25.000 (Extruder Prime Start)\nG92 A0 B0 (Reset after prime)\n"
      "G1 Z0.000000 F1000\nG1 X-141.0 Y-74.0 Z0.0 F1000 E0.0\nG92 E0\n"
      "G1 X-141.000 Y-74.000 Z0.000 F1500 A-1.30000; Retract \nG1 X-141.000 Y-74.000 Z0.200 F1380; Travel Move \n"
      "G1 X-9.400 Y-9.400 Z0.200 F9000; Travel Move \nG1 X-9.400 Y-9.400 Z0.200 F1500 A0.00000; Restart \n"
      "G1 X-9.400 Y9.400 Z0.200 F1800 A0.65725; Inset \nG1 X9.400 Y9.400 Z0.200 F1800 A1.31449; Inset \n"
      "G1 X9.400 Y-9.400 Z0.200 F1800 A1.97174; Inset \nG1 X-9.400 Y-9.400 Z0.200 F1800 A2.62898; Inset \n";
  Toolpath p = ParseGcode(text, "makerware.gcode");
  EXPECT_NEAR(BeadFilamentMm(p), 25 + 2.62898, 1e-9);  // was 25: the insets laid nothing
  EXPECT_NEAR(p.ExtrudedLength() / kMm, 25 + 2.62898, 1e-9);
  ASSERT_EQ(p.warnings.size(), 1u);  // the reading of E, said once
  EXPECT_EQ(p.warnings[0].line, 4);
  EXPECT_EQ(p.warnings[0].count, 2);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("E read as the active tool's axis"));
}

// FlashForge's FlashPrint writes .gx files: "xgcode 1.0\n\0", a 58-byte header of
// little-endian fields (0x10: the BMP's offset, 0x14: a PNG's, 0x18: the G-code's),
// the thumbnails, then the G-code text (a real Creator 4 export, as a project documents
// it, starts "M118 X16.63 Y16.63 Z21.22 T0"). It was refused for the thumbnail's NUL
// bytes ("not text"); the G-code is now read from its offset, lines counted from there.
TEST(GcodeRealFiles4, FlashForgeGxFilesAreReadFromTheirGcodeOffset) {
  auto le32 = [](uint32_t v) {
    std::string b(4, '\0');
    for (int i = 0; i < 4; ++i) b[size_t(i)] = char((v >> (8 * i)) & 0xff);
    return b;
  };
  const std::string bmp = std::string("BM") + le32(20) + std::string(14, '\0');  // 20 bytes with NULs
  const std::string gcode =
      "M118 X16.63 Y16.63 Z21.22 T0\nM140 S110 T0\nM104 S235 T0\nG90\nG1 Z50.000 F420\nM7 T0\nM6 T0\nM108 T0\n"
      "G1 X0 Y0 Z0.2 F3000\nG1 X10 Y0 E1 F1200\n";
  std::string header = std::string("xgcode 1.0\n") + '\0' + le32(0) + le32(58) + le32(78) + le32(78) + le32(100) +
                       le32(1) + le32(0);
  header.resize(58, '\0');
  Toolpath p = ParseGcode(header + bmp + gcode, "box.gx");
  EXPECT_NEAR(BeadFilamentMm(p), 1.0, 1e-9);
  ASSERT_FALSE(p.segments.empty());
  EXPECT_EQ(p.segments.back().line, 10);
  EXPECT_NEAR(p.segments.back().end_m.x(), 10 * kMm, 1e-12);
  // A header whose offset lies outside the file is refused, naming it.
  std::string bad = header;
  bad.replace(0x18, 4, le32(100000));
  EXPECT_THAT(test::ErrorOf([&] { ParseGcode(bad + bmp + gcode, "bad.gx"); }),
              HasSubstr("bad.gx: is a FlashForge .gx file whose header puts the G-code at byte 100000"));
}

// A file that prints with E and turns a rotary A beside it: its first move "A30 C45"
// was read with A as an extruder, so C turned "while it extrudes" and the file was
// refused at line 1 before its moves showed that it prints with E (found in review).
// The reading with A and B as axes now stands, since the whole file calls for it.
TEST(GcodeRealFiles4, ARotaryAxisBeforeTheFirstPrintMoveDoesNotRefuseTheFile) {
  const std::string text = "G1 X10 Y0 Z1 A30 C45\nG1 X20 Y0 E1\nG1 X20 Y10 E2\nG1 X10 Y10 E3\n";
  const Toolpath p = ParseGcode(text, "rotary.gcode");
  EXPECT_NEAR(BeadFilamentMm(p), 3.0, 1e-9);
  ASSERT_FALSE(p.warnings.empty());
  EXPECT_THAT(p.warnings[0].text, HasSubstr("A and B are no extruders here"));
  // A file that does print with A keeps the first read's error (the A word on the
  // moves outnumbers E): C turning while A extrudes is refused, naming the line.
  EXPECT_THAT(test::ErrorOf([] {
                ParseGcode("G1 X10 Y0 Z1 A30 C45\nG1 X20 Y0 A31\nG1 X20 Y10 A32\n", "a_prints.gcode");
              }),
              HasSubstr("a_prints.gcode:1: G1 moves the C axis while it extrudes"));
}

// In a file that prints with A (MakerBot, Mach3) E on a move goes onto the active
// tool's axis: said once, with the first line, rather than silently (found in review:
// a Mach3 purge "E5" without a later "G92 A0" made A1 a 4 mm retraction, 0 warnings).
TEST(GcodeRealFiles4, EReadAsTheActiveToolsAxisIsWarned) {
  const Toolpath p = ParseGcode("G1 X0 Y10 Z0.3 E5 F600\nG1 X10 Y10 A6\nG1 X10 Y20 A7\nG1 X0 Y20 A8\n", "m.gcode");
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].line, 1);
  EXPECT_THAT(p.warnings[0].text, HasSubstr("E read as the active tool's axis, A (T0) or B (T1)"));
  EXPECT_NEAR(BeadFilamentMm(p), 8.0, 1e-9);
}

// Found by tools/fuzz's fuzz_gcode (UBSan): a tool or coordinate-system number too
// large for an int was converted before its range was checked. Each is a clean error.
TEST(GcodeRealFiles4, HugeToolAndSystemNumbersAreErrors) {
  EXPECT_THAT(test::ErrorOf([] { ParseGcode("M221 S100 T600000000000\n", "t.gcode"); }),
              HasSubstr("t.gcode:1: M221 T must be a tool number"));
  EXPECT_THAT(test::ErrorOf([] { ParseGcode("M221 S100 D100000000000000000000\n", "t.gcode"); }),
              HasSubstr("t.gcode:1: M221 D must be a tool number"));
  EXPECT_THAT(test::ErrorOf([] { ParseGcode("G10 L2 P100000000000000000000 X1\n", "t.gcode"); }),
              HasSubstr("t.gcode:1: G10 L2 P must be a coordinate system 1-9"));
}

}  // namespace
}  // namespace lt

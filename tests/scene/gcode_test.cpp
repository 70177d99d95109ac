// G-code reading: Cura-like and PrusaSlicer-like files with hand-computed lengths,
// times and extrusion; arcs in all their forms against closed-form geometry;
// modes (G90/G91, M82/M83, G92, G20); malformed lines reported at file:line; and a
// generated file of many thousand lines whose totals are known in closed form.
#include "scene/gcode.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "test_util.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using test::ErrorOf;
using ::testing::HasSubstr;

const fs::path kGcode = fs::path(LT_SOURCE_DIR) / "tests/data/gcode";
constexpr double kMm = 1e-3;

// Checks a segment's geometry, extrusion and duration (lengths in mm, feed in mm/s).
void ExpectSegment(const ToolpathSegment& s, double length_mm, double extruded_mm, double feed_mm_s, int line) {
  EXPECT_NEAR(s.length_m, length_mm * kMm, 1e-12) << "line " << s.line;
  EXPECT_NEAR(s.extruded_m, extruded_mm * kMm, 1e-12) << "line " << s.line;
  EXPECT_NEAR(s.feed_m_s, feed_mm_s * kMm, 1e-12) << "line " << s.line;
  double expected_time = length_mm > 0 ? length_mm / feed_mm_s : std::abs(extruded_mm) / feed_mm_s;
  EXPECT_NEAR(s.Duration(), expected_time, 1e-12) << "line " << s.line;
  EXPECT_EQ(s.line, line);
}

TEST(Gcode, CuraFlavourLengthsTimesExtrusionLayersAndTypes) {
  Toolpath p = ReadGcode(kGcode / "cura_square.gcode", "cura_square.gcode");
  ASSERT_EQ(p.segments.size(), 14u);
  const auto& s = p.segments;
  ExpectSegment(s[0], 5, 0, 50, 13);                         // lift Z5 at F3000
  ExpectSegment(s[1], 0, -5, 40, 14);                        // retract E-5 at F2400: 0.125 s
  ExpectSegment(s[2], std::sqrt(200 + 4.8 * 4.8), 0, 100, 20);  // travel to (10, 10, 0.2)
  ExpectSegment(s[3], 0, 5, 40, 22);                         // unretract to E0
  for (int k = 0; k < 4; ++k) ExpectSegment(s[4 + k], 20, 1, 20, 23 + k);  // the square
  ExpectSegment(s[8], std::sqrt(50.0), 0, 100, 28);
  ExpectSegment(s[9], 10, 0.5, 20, 29);
  ExpectSegment(s[10], 0.2, 0, 100, 33);
  ExpectSegment(s[11], 10, 0.5, 20, 35);
  // End code: G91 then "G1 E-2" after the header's M82 is relative (Marlin's G91 sets E
  // relative too, cancelling M82): a 2 mm retraction. Z10 is relative: from 0.4 to 10.4.
  ExpectSegment(s[12], 0, -2, 45, 40);
  ExpectSegment(s[13], 10, 0, 45, 41);
  EXPECT_NEAR(s[13].end_m.z(), 10.4 * kMm, 1e-15);

  // Positions in metres, contiguous in space and time.
  EXPECT_TRUE(s[4].start_m.isApprox(Eigen::Vector3d(10, 10, 0.2) * kMm));
  EXPECT_TRUE(s[4].end_m.isApprox(Eigen::Vector3d(30, 10, 0.2) * kMm));
  for (size_t k = 1; k < s.size(); ++k) {
    EXPECT_EQ(s[k].start_m, s[k - 1].end_m) << k;
    EXPECT_EQ(s[k].t_start_s, s[k - 1].t_end_s) << k;
  }
  double total = 0.1 + 0.125 + std::sqrt(223.04) / 100 + 0.125 + 4 + std::sqrt(50.0) / 100 + 0.5 + 0.002 + 0.5 +
                 2.0 / 45 + 10.0 / 45;
  EXPECT_NEAR(p.Duration(), total, 1e-12);
  EXPECT_NEAR(p.ExtrudedLength(), (-5 + 5 + 4 + 0.5 + 0.5 - 2) * kMm, 1e-15);  // net

  // Layers and types from the comments.
  EXPECT_EQ(s[0].layer, ToolpathSegment::kNoLayer);
  EXPECT_EQ(s[2].layer, 0);
  EXPECT_EQ(s[11].layer, 1);
  ASSERT_EQ(p.type_names, (std::vector<std::string>{"WALL-OUTER", "SKIN"}));
  EXPECT_EQ(s[2].type, -1);  // the travel came before the first ;TYPE:
  EXPECT_EQ(s[4].type, 0);
  EXPECT_EQ(s[9].type, 1);
  EXPECT_EQ(s[11].type, 0);
  EXPECT_EQ(s[4].gcode, 1);
  EXPECT_EQ(s[8].gcode, 0);
  EXPECT_NEAR(p.header_layer_height_m, 0.2 * kMm, 1e-15);

  // Commands without effect on motion, counted.
  std::map<std::string, size_t> skipped = {{"M104", 1}, {"M107", 2}, {"M109", 1}, {"M140", 1},
                                           {"M190", 1}, {"M204", 2}, {"M205", 1}, {"M84", 1}};
  EXPECT_EQ(p.skipped_commands, skipped);
}

TEST(Gcode, PrusaFlavourArcsRelativeExtrusionAndHeights) {
  Toolpath p = ReadGcode(kGcode / "prusa_arcs.gcode", "prusa_arcs.gcode");
  const auto& s = p.segments;
  ASSERT_EQ(s.size(), 12u);
  ExpectSegment(s[0], 0.2, 0, 12, 10);
  ExpectSegment(s[1], 0, -0.8, 35, 15);  // M83: relative E
  ExpectSegment(s[2], std::sqrt(5000.0), 0, 150, 16);
  ExpectSegment(s[3], 0, 0.8, 35, 17);
  ExpectSegment(s[4], 10, 0.5, 30, 20);
  ExpectSegment(s[5], 5 * M_PI, 0.785, 30, 21);   // G3 quarter circle, I/J
  ExpectSegment(s[6], 5 * M_PI, 0.785, 30, 22);   // G2 quarter circle, R10
  ExpectSegment(s[7], 20 * M_PI, 3.14, 30, 23);   // G2 full circle
  ExpectSegment(s[8], 0.2, 0, 12, 27);
  ExpectSegment(s[9], 15 * M_PI, 2.356, 30, 29);  // G3 R-10: the 270-degree arc
  ExpectSegment(s[10], std::hypot(20 * M_PI, 1.0), 3.14, 30, 30);  // helix up 1 mm
  EXPECT_NEAR(s[11].Duration(), 0.5, 1e-15);      // G4 P500
  EXPECT_EQ(s[11].gcode, 4);

  // Arc geometry: centres, sweeps, and the points in between on the circle.
  EXPECT_TRUE(s[5].arc);
  EXPECT_TRUE(s[5].centre_m.isApprox(Eigen::Vector2d(60, 60) * kMm));
  EXPECT_NEAR(s[5].sweep_rad, M_PI / 2, 1e-12);
  EXPECT_TRUE(s[6].centre_m.isApprox(Eigen::Vector2d(70, 50) * kMm));
  EXPECT_NEAR(s[6].sweep_rad, -M_PI / 2, 1e-12);
  EXPECT_NEAR(s[7].sweep_rad, -2 * M_PI, 1e-12);
  EXPECT_TRUE(s[9].centre_m.isApprox(Eigen::Vector2d(90, 50) * kMm));
  EXPECT_NEAR(s[9].sweep_rad, 1.5 * M_PI, 1e-12);
  // Halfway along the G3 quarter circle: 45 degrees from (60, 50) around (60, 60).
  Eigen::Vector3d mid = s[5].PointAt(0.5);
  EXPECT_TRUE(mid.isApprox(Eigen::Vector3d(60 + 10 * std::sin(M_PI / 4), 60 - 10 * std::cos(M_PI / 4), 0.2) * kMm, 1e-12));
  // Counter-clockwise: the tangent at the start of the G3 is +x, of the G2 (R) +x too
  // (from the top of its circle, clockwise), at the bottom of the 270-degree arc -y.
  EXPECT_TRUE(s[5].TangentXy(0).isApprox(Eigen::Vector2d(1, 0), 1e-12));
  EXPECT_TRUE(s[6].TangentXy(0).isApprox(Eigen::Vector2d(1, 0), 1e-12));
  EXPECT_TRUE(s[9].TangentXy(0).isApprox(Eigen::Vector2d(0, -1), 1e-12));
  EXPECT_NEAR(s[10].PointAt(0.5).z(), 0.9 * kMm, 1e-15);
  EXPECT_TRUE(s[10].PointAt(0.5).head<2>().isApprox(Eigen::Vector2d(90, 40) * kMm, 1e-12));

  EXPECT_EQ(s[3].layer, 0);
  EXPECT_EQ(s[9].layer, 1);
  EXPECT_EQ(p.type_names, (std::vector<std::string>{"Custom", "External perimeter", "Perimeter"}));
  EXPECT_EQ(s[4].type, 1);
  EXPECT_EQ(s[10].type, 2);
  EXPECT_EQ(p.layer_height_m, (std::map<int, double>{{0, 0.2 * kMm}, {1, 0.2 * kMm}}));
  EXPECT_NEAR(p.header_layer_height_m, 0.2 * kMm, 1e-15);
  EXPECT_NEAR(p.filament_diameter_m, 1.75 * kMm, 1e-15);
  EXPECT_EQ(p.skipped_commands,
            (std::map<std::string, size_t>{{"M104", 1}, {"M107", 2}, {"M201", 1}, {"M73", 1}}));
  EXPECT_NEAR(p.ExtrudedLength(), (0.5 + 0.785 * 2 + 3.14 + 2.356 + 3.14) * kMm, 1e-15);
}

TEST(Gcode, PositionAtFollowsTheTimedPath) {
  Toolpath p = ReadGcode(kGcode / "cura_square.gcode");
  const ToolpathSegment& first_side = p.segments[4];  // (10,10) -> (30,10) in 1 s
  EXPECT_TRUE(p.PositionAt(first_side.t_start_s + 0.25).isApprox(Eigen::Vector3d(15, 10, 0.2) * kMm, 1e-12));
  EXPECT_EQ(p.SegmentIndexAt(first_side.t_start_s + 0.25), 4u);
  EXPECT_EQ(p.PositionAt(-1), Eigen::Vector3d::Zero());  // clamped to the start
  EXPECT_EQ(p.PositionAt(1e9), p.segments.back().end_m);
  EXPECT_EQ(p.PositionAt(std::nan("")), Eigen::Vector3d::Zero());
}

TEST(Gcode, ModesUnitsOffsetsAndSyntax) {
  // G92 shifts the logical origin; G20 inches (also for F); N is dropped, a checksum * checked;
  // lower case letters, parenthesised comments and compact words are read.
  Toolpath p = ParseGcode(
      "G1 X10 F600\n"
      "G92 X0 E0\n"
      "G1 X5 E1\n"            // machine x = 15
      "N7 g1 x6 e2 (note)*39\n"  // machine x = 16; 39: XOR of the bytes before *
      "G20\n"
      "G1X1E1F60\n"           // 1 inch: machine x 25.4 + 10, 1 inch/s
      "G21\n"
      "G91\n"
      "M83\n"
      "G1 X-1 E0.5 F600\n"
      "G90\n"
      "G1 Y2 E0.5\n",         // M83 keeps E relative under G90
      "t.gcode");
  ASSERT_EQ(p.segments.size(), 6u);
  EXPECT_NEAR(p.segments[1].end_m.x(), 15 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[2].end_m.x(), 16 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[3].end_m.x(), 35.4 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[3].extruded_m, 23.4 * kMm, 1e-15);  // E from 2 mm to 1 inch
  EXPECT_NEAR(p.segments[3].feed_m_s, 25.4 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[4].end_m.x(), 34.4 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[4].extruded_m, 0.5 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[5].extruded_m, 0.5 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[5].end_m.y(), 2 * kMm, 1e-15);
  EXPECT_EQ(p.segments[2].line, 4);

  // G92 without axes zeroes all; G28 X homes only x, as a travel move at the homing
  // speed; a move without change makes no segment; F alone only sets the feed.
  Toolpath h = ParseGcode("G1 X3 Y4 F6000\nG92\nG1 X1\nG1 X1\nG1 F60\nG28 X\n", "h.gcode");
  ASSERT_EQ(h.segments.size(), 3u);
  EXPECT_NEAR(h.segments[1].end_m.x(), 4 * kMm, 1e-15);
  EXPECT_EQ(h.segments[2].gcode, 28);
  EXPECT_TRUE(h.segments[2].end_m.isApprox(Eigen::Vector3d(0, 4, 0) * kMm));
  EXPECT_NEAR(h.segments[2].Duration(), 4.0 / 50, 1e-12);  // 4 mm at 50 mm/s, not F60's 1 mm/s
}

// Moves before the first F run at Marlin's power-on feed rate (1500 mm/min =
// 25 mm/s) and are counted with the line of the first; homing runs at Marlin's
// homing speed (50 mm/s for X), before and after an F; moves after an F use it.
TEST(Gcode, MovesBeforeAnyFeedRateRunAtThePowerOnRate) {
  Toolpath p = ParseGcode("G28\nG1 X10\nG0 Y5\nG1 Z0 F600\nG1 X20\n", "g.gcode");
  ASSERT_EQ(p.segments.size(), 3u);  // homing from the origin and the F-only line do not move
  EXPECT_NEAR(p.segments[0].t_end_s - p.segments[0].t_start_s, 10.0 / 25.0, 1e-12);
  EXPECT_NEAR(p.segments[1].t_end_s - p.segments[1].t_start_s, 5.0 / 25.0, 1e-12);
  EXPECT_NEAR(p.segments[2].t_end_s - p.segments[2].t_start_s, 10.0 / 10.0, 1e-12);
  EXPECT_EQ(p.moves_at_power_on_feed, 2);
  EXPECT_EQ(p.first_power_on_feed_line, 2);
  Toolpath homed = ParseGcode("G1 X10 F1200\nG28 X\n", "g.gcode");
  EXPECT_EQ(homed.moves_at_power_on_feed, 0);
  EXPECT_NEAR(homed.segments[1].t_end_s - homed.segments[1].t_start_s, 10.0 / 50.0, 1e-12);  // homing speed
}

TEST(Gcode, MalformedLinesAreErrorsAtFileAndLine) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {"G1 X10 F600\nG1 X Y5\n", "g.gcode:2: X without a number"},
      {"G1 X10 F600\nG1 Xnan\n", "g.gcode:2: X is not a finite number"},
      {"G1 X10 F600\nG1 X1.2.3\n", "g.gcode:2: X has a malformed number \"1.2.3\""},
      {"G1 X10 F600\nG1 X1 X2\n", "g.gcode:2: X given twice"},
      {"G1 X10 F600\nG1 X1 Q2\n", "g.gcode:2: G1 takes no parameter Q"},
      {"G1 X10 F600\nG1 X1 T1\n", "g.gcode:2: one command per line: found T after the command"},
      {"G1 X10 F0\n", "g.gcode:1: feed rate F must be > 0, got 0"},
      {"G1 X10 F600\n\nG2 X20 Y10\n", "g.gcode:3: G2 needs I/J (centre offset) or R (radius)"},
      {"G1 X10 F600\nG3 X20 I5 R5\n", "g.gcode:2: G3 takes I/J or R, not both"},
      {"G1 X10 F600\nG2 X20 R0\n", "g.gcode:2: G2 with zero radius R"},
      {"G1 X10 F600\nG2 X20 I0 J0\n", "g.gcode:2: G2 with zero radius (I and J are 0)"},
      {"G1 X10 F600\nG2 X20 R4\n", "g.gcode:2: G2 radius 4 is too small for a chord of 10"},
      {"G1 X10 F600\nG2 X10 R4\n", "g.gcode:2: G2 with R needs an end point away from the start"},
      {"G1 X10 F600\nG2 X20 I4\n", "g.gcode:2: G2 end point is not on the arc: radius 4 at the start, 6 at the end"},
      {"G1 X10 F600\nG18\nG2 X20 J5\n", "g.gcode:3: G2 takes no parameter J"},  // ZX: K and I
      {"X10 Y10\n", "g.gcode:1: expected a command (G, M or T)"},
      {"G\n", "g.gcode:1: G without a number"},
      {"G4 P-5\n", "g.gcode:1: G4 dwell time must be >= 0"},
      {";LAYER:x\n", "g.gcode:1: LAYER comment without a number"},
      {";LAYER:1.5\n", "g.gcode:1: LAYER comment needs an integer"},
      {"G90 X1\n", "g.gcode:1: G90 takes no parameter X"},
      {"GCDE\x01\x00\x00\x00", "g.gcode: is a binary G-code file (PrusaSlicer's .bgcode"},
      {"PK\x03\x04\x14", "g.gcode: is a zip archive, not G-code (Bambu Studio's and OrcaSlicer's .gcode.3mf"},
      {"G1 X10 F600\nG1 X20 E0.1:0.2\n", "g.gcode:2: E with several values (\"0.1:0.2\": RepRapFirmware's amounts per drive) is not supported"},
  };
  for (const auto& c : cases) {
    EXPECT_THAT(ErrorOf([&] { ParseGcode(c.text, "g.gcode"); }), HasSubstr(c.expected)) << c.text;
  }
  // A NUL byte (a binary file): said so at its line.
  const std::string with_nul("G1 X10 F600\nG1 X2\0\n", 18);
  EXPECT_THAT(ErrorOf([&] { ParseGcode(with_nul, "g.gcode"); }),
              HasSubstr("g.gcode:2: a NUL byte: this is not a text G-code file"));
  EXPECT_THAT(ErrorOf([&] { ReadGcode(kGcode / "missing.gcode", "missing.gcode"); }),
              HasSubstr("missing.gcode: cannot open file"));
  // Unknown commands are not parsed: a message with any text is fine.
  Toolpath p = ParseGcode("M117 Printing X... 50%\nM600\nG29.1 Q\nT1\n", "g.gcode");
  EXPECT_EQ(p.skipped_commands,
            (std::map<std::string, size_t>{{"G29.1", 1}, {"M117", 1}, {"M600", 1}, {"T1", 1}}));
  EXPECT_TRUE(p.segments.empty());
}

// What OrcaSlicer and Bambu Studio write for Klipper and Bambu printers, and what
// Simplify3D writes: extended commands, other layer and feature comments, a byte
// order mark, CR LF line ends and "%" marks.
TEST(Gcode, KlipperBambuAndSimplify3dDialects) {
  Toolpath p = ParseGcode(
      "\xEF\xBB\xBF; generated by OrcaSlicer\r\n"
      "%\r\n"
      "EXCLUDE_OBJECT_DEFINE NAME=part CENTER=10,10 POLYGON=[[0,0],[20,0],[20,20]]\r\n"
      "PRINT_START BED=60 HOTEND=210\r\n"
      "nozzle_clean\r\n"
      "M204 P500 R1000 T500\r\n"
      "M83\r\n"
      "; CHANGE_LAYER\r\n"
      "; LAYER_HEIGHT: 0.25\r\n"
      "; FEATURE: Outer wall\r\n"
      "EXCLUDE_OBJECT_START NAME=part\r\n"
      "G1 X10 Y0 Z0.25 E0.5 F600\r\n"
      "EXCLUDE_OBJECT_END NAME=part\r\n"
      "; CHANGE_LAYER\r\n"
      ";TYPE:Inner wall\r\n"
      "G1 X10 Y10 E0.5\r\n"
      "%\r\n",
      "k.gcode");
  ASSERT_EQ(p.segments.size(), 2u);
  EXPECT_NEAR(p.segments[0].length_m, std::sqrt(100 + 0.0625) * kMm, 1e-15);
  EXPECT_NEAR(p.segments[1].extruded_m, 0.5 * kMm, 1e-15);  // M83: relative E
  EXPECT_EQ(p.segments[0].line, 12);
  EXPECT_EQ(p.segments[0].layer, 0);
  EXPECT_EQ(p.segments[1].layer, 1);
  EXPECT_EQ(p.type_names, (std::vector<std::string>{"Outer wall", "Inner wall"}));
  EXPECT_DOUBLE_EQ(p.layer_height_m.at(0), 0.25 * kMm);
  EXPECT_EQ(p.skipped_commands,
            (std::map<std::string, size_t>{{"EXCLUDE_OBJECT_DEFINE", 1}, {"EXCLUDE_OBJECT_END", 1},
                                           {"EXCLUDE_OBJECT_START", 1}, {"M204", 1}, {"NOZZLE_CLEAN", 1},
                                           {"PRINT_START", 1}}));
  EXPECT_EQ(p.SkippedCommandsNote(),
            "skipped 6 commands without effect on motion: EXCLUDE_OBJECT_DEFINE x1, EXCLUDE_OBJECT_END x1, "
            "EXCLUDE_OBJECT_START x1, M204 x1, NOZZLE_CLEAN x1, PRINT_START x1");
  Toolpath many = ParseGcode("M104 S1\nM104 S2\nM1\nM9\nM3\nM4\nM5\nM6\nM7\nM8\n", "m.gcode");
  EXPECT_EQ(many.SkippedCommandsNote(),
            "skipped 10 commands without effect on motion: M104 x2, M1 x1, M3 x1, M4 x1, M5 x1, M6 x1, M7 x1, M8 x1 "
            "and 1 other kinds");
  EXPECT_EQ(ParseGcode("G1 X1 F60\n", "g.gcode").SkippedCommandsNote(), "");
  // A line number is N and digits: "N7 G1" is G1, "NOZZLE_CLEAN" a command of its own.
  EXPECT_THAT(ErrorOf([] { ParseGcode("N7 X1\n", "n.gcode"); }), HasSubstr("n.gcode:1: expected a command"));
}

TEST(Gcode, ArcWithinRoundingOfItsCircleIsAccepted) {
  // I/J written to 3 decimals put the end 0.0005 mm off the circle: accepted, and
  // the radius moves linearly from start to end so the path stays continuous.
  Toolpath p = ParseGcode("G1 X10 Y0 F600\nG3 X0 Y10.0005 I-10 J0\n", "g.gcode");
  ASSERT_EQ(p.segments.size(), 2u);
  EXPECT_TRUE(p.segments[1].PointAt(1).isApprox(Eigen::Vector3d(0, 10.0005, 0) * kMm, 1e-12));
  EXPECT_NEAR(p.segments[1].length_m, 10.00025 * M_PI / 2 * kMm, 1e-12);
}

// A generated print: `layers` layers of a zig-zag of `lines` lines 40 mm long, 0.4 mm
// apart, with a travel back to the corner and a layer change between layers. Every
// total is known in closed form.
std::string ZigZag(int layers, int lines) {
  std::ostringstream g;
  g << ";FLAVOR:Marlin\n;Layer height: 0.2\nM82\nG92 E0\nG1 F6000 X0 Y0 Z0.2\n";
  double e = 0;
  for (int layer = 0; layer < layers; ++layer) {
    g << ";LAYER:" << layer << "\n;TYPE:FILL\nM204 S1000\n";
    if (layer > 0) g << "G0 F6000 X0 Y0 Z" << 0.2 * (layer + 1) << "\n";
    double y = 0;
    for (int k = 0; k < lines; ++k) {
      double x = (k % 2 == 0) ? 40 : 0;
      e += 2;
      g << "G1 F1200 X" << x << " Y" << y << " E" << e << "\n";
      y += 0.4;
      if (k + 1 < lines) {
        e += 0.02;
        g << "G1 X" << x << " Y" << y << " E" << e << "\n";
      }
    }
  }
  return g.str();
}

TEST(Gcode, ManyThousandLinesAddUp) {
  const int layers = 20, lines = 200;  // 8000 moves, about 8100 lines
  std::string text = ZigZag(layers, lines);
  Toolpath p = ParseGcode(text, "zigzag.gcode");
  ASSERT_EQ(p.segments.size(), size_t(1 + layers * (2 * lines - 1) + (layers - 1)));
  double step = 0.4 * (lines - 1);           // y extent of one layer
  double travel_back = 0;                    // from the last line's end to the corner, up 0.2
  double x_end = (lines % 2 == 1) ? 40 : 0;  // where each layer ends
  travel_back = std::sqrt(x_end * x_end + step * step + 0.04);
  double print = layers * (lines * 40.0 + (lines - 1) * 0.4);
  EXPECT_NEAR(p.PathLength(), (0.2 + print + (layers - 1) * travel_back) * kMm, 1e-9);
  EXPECT_NEAR(p.ExtrudedLength(), layers * (lines * 2.0 + (lines - 1) * 0.02) * kMm, 1e-9);
  EXPECT_NEAR(p.Duration(), 0.2 / 100 + print / 20 + (layers - 1) * travel_back / 100, 1e-6);
  EXPECT_EQ(p.segments.back().layer, layers - 1);
  EXPECT_EQ(p.skipped_commands.at("M204"), size_t(layers));
  // Time lookup agrees with the segment times everywhere.
  for (size_t k = 0; k < p.segments.size(); k += 97) {
    const ToolpathSegment& s = p.segments[k];
    double t = 0.5 * (s.t_start_s + s.t_end_s);
    EXPECT_EQ(p.SegmentIndexAt(t), k);
    EXPECT_TRUE(p.PositionAt(t).isApprox(0.5 * (s.start_m + s.end_m), 1e-12));
  }
}

}  // namespace
}  // namespace lt

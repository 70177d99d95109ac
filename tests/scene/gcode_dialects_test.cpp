// G-code in less common forms: RepRapFirmware's homing and motor moves (G1 H1/H2),
// line ends of every kind (LF, CR LF, classic Mac OS's lone CR, mixed), ';' inside a
// parenthesised comment, G28's axis order and homing speeds, E's mode under G90/G91
// and M82/M83, text parameters (messages, file names, quoted strings), and Cura's "one
// at a time" sequence (objects printed one after another, ;LAYER: numbered from 0 again).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene/bead_geometry.h"
#include "scene/gcode.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using ::testing::HasSubstr;
constexpr double kMm = 1e-3;

// RepRapFirmware's homing file form: H2 lifts Z as an ordinary move; H1 runs towards
// the endstop and ends where the axis homes (0), at the line's feed, laying nothing;
// H0 is an ordinary move.
TEST(GcodeDialects, RepRapFirmwareHomingAndMotorMovesAreNoPrintMoves) {
  Toolpath p = ParseGcode(
      "G91\n"
      "G1 H2 Z5 F600\n"          // 5 mm up at 10 mm/s: 0.5 s
      "G1 H1 X-240 F3000\n"      // homes x from 0: no motion
      "G90\n"
      "G1 H0 X30 Y40 F6000\n"    // 50 mm at 100 mm/s
      "G1 H1 X-10 Y-10 F3000\n"  // both home: 50 mm back to (0, 0) at 50 mm/s
      "G92 X5\n"                 // logical x = 5 at machine 0
      "G1 H4 X-300\n"            // homing clears the G92 offset
      "G1 X10 E1\n",
      "homeall.g");
  ASSERT_EQ(p.segments.size(), 4u);
  EXPECT_TRUE(p.segments[0].end_m.isApprox(Eigen::Vector3d(0, 0, 5) * kMm));
  EXPECT_NEAR(p.segments[0].Duration(), 0.5, 1e-12);
  EXPECT_NEAR(p.segments[1].Duration(), 0.5, 1e-12);
  EXPECT_EQ(p.segments[2].gcode, 28);
  EXPECT_EQ(p.segments[2].line, 6);
  EXPECT_NEAR(p.segments[2].end_m.head<2>().norm(), 0, 1e-15);
  EXPECT_NEAR(p.segments[2].end_m.z(), 5 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[2].Duration(), 1.0, 1e-12);
  EXPECT_EQ(p.segments[2].extruded_m, 0);
  EXPECT_NEAR(p.segments[3].end_m.x(), 10 * kMm, 1e-15);  // X10 from machine 0, no offset left
  EXPECT_EQ(p.LayerCount(), 1);

  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X1 F600\nG1 H2 X5 E1\n", "m.gcode"); }),
              HasSubstr("m.gcode:2: G1 H2 with E is not supported"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X1 F600\nG1 H5 X5\n", "m.gcode"); }),
              HasSubstr("m.gcode:2: G1 H must be 0, 1, 2, 3 or 4"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X1 F600\nG2 H1 X5 I1\n", "m.gcode"); }),
              HasSubstr("m.gcode:2: G2 takes no parameter H"));
}

// The same three moves with every kind of line end: the same path, and the lines
// counted alike (an error names the same line).
TEST(GcodeDialects, LineEndsOfEveryKindAreRead) {
  const std::string lines[] = {";LAYER:0", "G1 X10 E1 F600", "G1 Y10 E2", ";LAYER:1", "G1 X0 E3 Z0.2", "G1 Q1"};
  const std::string ends[][6] = {{"\n", "\n", "\n", "\n", "\n", "\n"},
                                 {"\r", "\r", "\r", "\r", "\r", "\r"},
                                 {"\r\n", "\n", "\r", "\r\n", "\r", "\n"}};
  for (const auto& end : ends) {
    std::string text;
    for (int k = 0; k < 5; ++k) text += lines[k] + end[k];
    Toolpath p = ParseGcode(text, "e.gcode");
    ASSERT_EQ(p.segments.size(), 3u) << int(end[0][0]);
    EXPECT_EQ(p.segments[2].layer, 1);
    EXPECT_EQ(p.segments[2].line, 5);
    EXPECT_NEAR(p.ExtrudedLength(), 3 * kMm, 1e-15);
    EXPECT_EQ(p.LayerCount(), 2);
    EXPECT_THAT(ErrorOf([&] { ParseGcode(text + lines[5] + end[5], "e.gcode"); }), HasSubstr("e.gcode:6: G1 takes no"));
  }
  // UTF-16 is named as such (it was "a NUL byte" on line 1).
  EXPECT_THAT(ErrorOf([] { ParseGcode(std::string("\xFF\xFEG\0001\0", 6), "u.gcode"); }),
              HasSubstr("u.gcode: is UTF-16 text"));
}

// A parenthesised comment runs to its ')': a ';' or '*' inside it neither ends the
// line's code nor starts a checksum.
TEST(GcodeDialects, SemicolonInsideParenthesesIsPartOfTheComment) {
  Toolpath p = ParseGcode("G1 F600\nG1 X10 (move; fast) Y5 E1\nG1 (a*b) X0 ; back (the ; rest) E9\n", "p.gcode");
  ASSERT_EQ(p.segments.size(), 2u);
  EXPECT_TRUE(p.segments[0].end_m.isApprox(Eigen::Vector3d(10, 5, 0) * kMm));
  EXPECT_NEAR(p.segments[0].extruded_m, 1 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[1].end_m.x(), 0, 1e-15);
  EXPECT_EQ(p.segments[1].extruded_m, 0);  // the E9 after ';' is comment
  // A checksum after a comment with ';' covers the bytes before '*', comment included.
  const std::string body = "N5 G1 X3 (a; b)";
  int sum = 0;
  for (char c : body) sum ^= static_cast<unsigned char>(c);
  Toolpath c = ParseGcode(body + "*" + std::to_string(sum) + "\n", "c.gcode");
  ASSERT_EQ(c.segments.size(), 1u);
  EXPECT_NEAR(c.segments[0].end_m.x(), 3 * kMm, 1e-15);
}

// Text parameters: a '*' in a message or file name (M117, M23, ...) is text unless only
// a checksum follows it; a quoted string (RepRapFirmware's M291 P"...") holds ';', '('
// and '*' as text. G5 (a Bezier move) outside the XY plane is refused, as Marlin does
// (G5 itself: GcodeRealFiles6.MarlinBezierMoveIsRunAsChords).
TEST(GcodeDialects, MessagesFileNamesAndQuotedStringsHoldTheirText) {
  Toolpath p = ParseGcode(
      "G1 F600\nM117 Layer 5 * of 10\nM23 my*file.gco\nM291 P\"Insert; (filament\" R\"Hi*\" S2 (a note)\n"
      "G1 X10 E1\n",
      "t.gcode");
  ASSERT_EQ(p.segments.size(), 1u);
  EXPECT_EQ(p.segments[0].line, 5);
  EXPECT_EQ(p.skipped_commands.at("M117"), 1u);
  EXPECT_EQ(p.skipped_commands.at("M291"), 1u);
  // Prusa firmware's MMU tool commands without a number are skipped by name.
  Toolpath mmu = ParseGcode("G1 F600\nTx\nTc\nT?\nG1 X1 E1\n", "t.gcode");
  EXPECT_EQ(mmu.skipped_commands.at("TX"), 1u);
  EXPECT_EQ(mmu.skipped_commands.at("T?"), 1u);
  EXPECT_EQ(mmu.segments.size(), 1u);
  EXPECT_THAT(ErrorOf([] { ParseGcode("T\n", "t.gcode"); }), HasSubstr("t.gcode:1: T without a number"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("M117 Hi*5\n", "t.gcode"); }), HasSubstr("t.gcode:1: checksum *5 does not match"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X1 F600 *x\n", "t.gcode"); }), HasSubstr("t.gcode:1: checksum after '*'"));
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 F600\nG18\nG5 I0 J3 P0 Q-3 X2 Y2 E1\n", "t.gcode"); }),
              HasSubstr("t.gcode:3: G5 (Bezier move) needs the XY plane (G17)"));
}

// G28 homes X, then Y, then Z, at Marlin's homing speeds (50, 50 and 4 mm/s),
// whatever the modal F, which it leaves for the moves after it.
TEST(GcodeDialects, HomingMovesEachAxisInTurnAtItsHomingSpeed) {
  Toolpath p = ParseGcode("G1 X30 Y40 Z8 F600\nG28\nG1 X10\n", "h.gcode");
  ASSERT_EQ(p.segments.size(), 5u);
  const Eigen::Vector3d ends[] = {{0, 40, 8}, {0, 0, 8}, {0, 0, 0}, {10, 0, 0}};
  const double durations[] = {30.0 / 50, 40.0 / 50, 8.0 / 4, 10.0 / 10};
  for (int k = 0; k < 4; ++k) {
    EXPECT_TRUE(p.segments[k + 1].end_m.isApprox(ends[k] * kMm, 1e-12)) << k;
    EXPECT_NEAR(p.segments[k + 1].Duration(), durations[k], 1e-12) << k;
    EXPECT_EQ(p.segments[k + 1].gcode, k < 3 ? 28 : 1) << k;
  }
  // "G28 Z Y": Y homes before Z, whatever the order of the words; x stays.
  Toolpath q = ParseGcode("G1 X10 Y20 Z2 F600\nG28 Z Y\n", "h.gcode");
  ASSERT_EQ(q.segments.size(), 3u);
  EXPECT_TRUE(q.segments[1].end_m.isApprox(Eigen::Vector3d(10, 0, 2) * kMm));
  EXPECT_TRUE(q.segments[2].end_m.isApprox(Eigen::Vector3d(10, 0, 0) * kMm));
  EXPECT_NEAR(q.segments[2].Duration(), 0.5, 1e-12);
}

// E's mode: relative under G91 and after M83. Cura's end script "G91 / G1 E-3 / G90"
// after its header's M82 retracts 3 mm (Marlin's G91 cancels M82), not to E = -3; an
// M83 holds through G91 and G90 (Bambu Studio and the Klipper templates rely on it).
TEST(GcodeDialects, G91MakesERelativeAfterM82AndM83HoldsThroughG90) {
  Toolpath p = ParseGcode("M82\nG1 X1 E5 F600\nG91\nG1 E-3\nG1 Z10\nG90\nG1 X2 E4\n", "end.gcode");
  ASSERT_EQ(p.segments.size(), 4u);
  EXPECT_NEAR(p.segments[1].extruded_m, -3 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[1].Duration(), 0.3, 1e-12);
  EXPECT_NEAR(p.segments[3].extruded_m, 2 * kMm, 1e-15);  // absolute again: E from 2 to 4
  Toolpath q = ParseGcode("M83\nG91\nG1 Z1 F600\nG90\nG1 X1 E0.5\nG1 X2 E0.5\n", "m83.gcode");
  ASSERT_EQ(q.segments.size(), 3u);
  EXPECT_NEAR(q.ExtrudedLength(), 1 * kMm, 1e-15);
}

// Several commands on one line, as CNC-style headers write them ("G21 G90",
// "G90 G94 G17"), run in turn; each takes the words up to the next G or M word.
// (Before: "one command per line: found G after the command".) A skipped
// command's text is not split: "M486 AMesh2" names an object, it is no M2.
TEST(GcodeDialects, SeveralCommandsOnOneLineRunInTurn) {
  const Toolpath p = ParseGcode(
      "G20 G91\n"                  // inches, relative
      "G1 X1 F60 G90 M83\n"        // 1 in along x at 1 in/s, then absolute, E relative
      "G1 X2 E0.1 G21\n"           // to x = 2 in, extruding 0.1 in; then millimetres
      "G1 X60.8 E2\n"              // to 60.8 mm (0.4 in on), 2 mm of filament
      "M486 AMesh2\nG1 X70 E1\n",  // an object's name, then on
      "multi.gcode");
  ASSERT_EQ(p.segments.size(), 4u);
  EXPECT_TRUE(p.segments[0].end_m.isApprox(Eigen::Vector3d(25.4, 0, 0) * kMm));
  EXPECT_NEAR(p.segments[0].Duration(), 1.0, 1e-12);
  EXPECT_TRUE(p.segments[1].end_m.isApprox(Eigen::Vector3d(50.8, 0, 0) * kMm));
  EXPECT_NEAR(p.segments[1].extruded_m, 2.54 * kMm, 1e-12);
  EXPECT_TRUE(p.segments[2].end_m.isApprox(Eigen::Vector3d(60.8, 0, 0) * kMm));
  EXPECT_NEAR(p.segments[2].extruded_m, 2 * kMm, 1e-12);
  EXPECT_EQ(p.program_end_line, 0);
  EXPECT_EQ(p.segments.size(), 4u);
  EXPECT_THAT(ErrorOf([] { ParseGcode("G90 G1 X1 T2\n", "t.gcode"); }),
              HasSubstr("t.gcode:1: one command per line: found T after the command"));
}

// Mach3 and Machinekit flavours (Cura, PrusaSlicer) extrude on A, MakerBot's second
// extruder on B: each is an extruder axis with its own position, reset by G92.
TEST(GcodeDialects, ExtruderAxesAAndBAreExtrusion) {
  Toolpath p = ParseGcode("G1 X10 A1 F600\nG1 X20 A3\nG1 X30 B0.5\nG92 A0\nG1 X40 A0.25\nG2 X50 I5 A1.25\n",
                          "mach3.gcode");
  ASSERT_EQ(p.segments.size(), 5u);
  const double fed_mm[] = {1, 2, 0.5, 0.25, 1};
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(p.segments[k].extruded_m, fed_mm[k] * kMm, 1e-15) << k;
  EXPECT_EQ(p.LayerCount(), 1);
  // Kiri:Moto (which can map E to A) states its layer height as "; sliceHeight = h".
  EXPECT_NEAR(ParseGcode("; Generated by Kiri:Moto 4.1\n; sliceHeight = 0.25\n", "k.gcode").header_layer_height_m,
              0.25 * kMm, 1e-15);
  EXPECT_THAT(ErrorOf([] { ParseGcode("G1 X1 E1 A1 F600\n", "m.gcode"); }),
              HasSubstr("m.gcode:1: both E and A: one extruder axis per move"));
}

// Volumetric extrusion (M200 D, PrusaSlicer's "use_volumetric_e"): E is mm^3; the
// toolpath holds the length of the M200 diameter's filament, and the beads its volume.
TEST(GcodeDialects, VolumetricExtrusionReadsEAsCubicMillimetres) {
  Toolpath p = ParseGcode("M83\nM200 D2.85\nG1 X10 E6 F600\nM200 D0\nG1 X20 E1\nM200 S1\nG1 X30 E6\n", "vol.gcode");
  ASSERT_EQ(p.segments.size(), 3u);
  const double area_mm2 = M_PI * 0.25 * 2.85 * 2.85;
  EXPECT_NEAR(p.segments[0].extruded_m, 6 / area_mm2 * kMm, 1e-15);
  EXPECT_NEAR(p.segments[1].extruded_m, 1 * kMm, 1e-15);  // D0: lengths again
  EXPECT_NEAR(p.segments[2].extruded_m, 6 / area_mm2 * kMm, 1e-15);  // S1: on with the last D
  EXPECT_NEAR(p.filament_diameter_m, 2.85 * kMm, 1e-15);
  Mesh first = BeadMeshUpTo(p, p.segments[0].t_end_s, BeadOptions{.layer_height_m = 0.2e-3});
  EXPECT_NEAR(MeshVolume(first), 6e-9, 1e-3 * 6e-9);  // 6 mm^3
  EXPECT_THAT(ErrorOf([] { ParseGcode("M200 D-1\n", "v.gcode"); }), HasSubstr("v.gcode:1: M200 D"));
}

// Cura's "one at a time": each object from its layer 0 at the bed, ;LAYER: numbered
// from 0 again, a travel above the printed objects between them.
std::string OneAtATime() {
  std::string g = ";FLAVOR:Marlin\n;Layer height: 0.2\nM82\nG92 E0\n";
  double e = 0;
  for (int object = 0; object < 2; ++object) {
    const double x0 = 20 + 40 * object;
    g += ";LAYER_COUNT:3\n";
    for (int layer = 0; layer < 3; ++layer) {
      const double z = 0.3 + 0.2 * layer;  // a 0.3 mm first layer
      g += ";LAYER:" + std::to_string(layer) + "\nG0 F6000 X" + std::to_string(x0) + " Y20 Z" + std::to_string(z) +
           "\n;TYPE:WALL-OUTER\n";
      for (const char* corner : {" X%g Y20", " X%g Y30"}) {
        e += 0.5;
        char buf[64];
        std::snprintf(buf, sizeof buf, corner, x0 + 10);
        g += std::string("G1 F1200") + buf + " E" + std::to_string(e) + "\n";
      }
    }
    g += "G0 F6000 Z6.2\n";  // above the objects, to the next one
  }
  return g;
}

TEST(GcodeDialects, CuraOneAtATimeLayersHeightsAndGrowth) {
  Toolpath p = ParseGcode(OneAtATime(), "seq.gcode");
  EXPECT_EQ(p.LayerSequences(), 2);
  EXPECT_EQ(p.LayerCount(), 6);  // 3 in each object
  // The layer numbers stay the file's: the second object's first layer is layer 0.
  std::vector<int> layers;
  for (const auto& s : p.segments) {
    if (s.LaysBead()) layers.push_back(s.layer);
  }
  EXPECT_THAT(layers, ::testing::ElementsAre(0, 0, 1, 1, 2, 2, 0, 0, 1, 1, 2, 2));
  // Each object's first layer stands on the bed (0.3 mm), the others on the layer below.
  std::vector<double> heights = BeadLayerHeights(p);
  std::vector<double> bead_heights_mm;
  for (size_t k = 0; k < p.segments.size(); ++k) {
    if (p.segments[k].LaysBead()) bead_heights_mm.push_back(std::round(heights[k] / kMm * 1e6) / 1e6);
  }
  EXPECT_THAT(bead_heights_mm, ::testing::ElementsAre(0.3, 0.3, 0.2, 0.2, 0.2, 0.2, 0.3, 0.3, 0.2, 0.2, 0.2, 0.2));
  // Growth follows print order: when the second object starts, the first is complete
  // (its filament, 3 mm) and the second has nothing; at the end both are.
  const double filament_area = M_PI * 0.25 * 1.75e-3 * 1.75e-3;
  double t_second = 0;
  for (const auto& s : p.segments) {
    if (s.LaysBead() && s.start_m.x() > 50 * kMm) {
      t_second = s.t_start_s;
      break;
    }
  }
  ASSERT_GT(t_second, 0);
  Mesh first = BeadMeshUpTo(p, t_second);
  EXPECT_NEAR(MeshVolume(first), 3 * kMm * filament_area, 1e-3 * 3 * kMm * filament_area);
  for (const auto& v : first.positions) EXPECT_LT(v.x(), 35 * kMm);
  EXPECT_NEAR(MeshVolume(BeadMeshUpTo(p, p.Duration())), 6 * kMm * filament_area, 1e-3 * 6 * kMm * filament_area);
}

// The same print without layer comments (Slic3r's "complete objects", a streamed file):
// layers from the extrusion heights, a new run where the height drops to the next
// object's first layer.
TEST(GcodeDialects, SequentialObjectsWithoutLayerCommentsStartTheirLayersAgain) {
  std::string text = OneAtATime();
  for (size_t at; (at = text.find(";LAYER:")) != std::string::npos;) text.erase(at, text.find('\n', at) + 1 - at);
  Toolpath p = ParseGcode(text, "seq.gcode");
  EXPECT_TRUE(p.layers_from_z);
  EXPECT_EQ(p.LayerSequences(), 2);
  EXPECT_EQ(p.LayerCount(), 6);
  std::vector<int> layers;
  for (const auto& s : p.segments) {
    if (s.LaysBead()) layers.push_back(s.layer);
  }
  EXPECT_THAT(layers, ::testing::ElementsAre(0, 0, 1, 1, 2, 2, 0, 0, 1, 1, 2, 2));
}

}  // namespace
}  // namespace lt

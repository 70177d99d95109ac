// Files that print with several tools (tool changers, IDEX printers, multi-material units,
// Klipper's extruders): each tool's filament drawn back, and Klipper's ACTIVATE_EXTRUDER.
// See docs/sequences.md, "Several tools".
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "error_of.h"
#include "scene/gcode.h"

namespace lt {
namespace {

using ::testing::HasSubstr;
constexpr double kMm = 1e-3;

// The filament laid by each segment with X/Y motion, in the file's order (mm).
std::vector<double> BeadsLaidMm(const Toolpath& p) {
  std::vector<double> laid;
  for (const ToolpathSegment& s : p.segments) {
    if (s.xy_length_m > 0 && s.extruded_m > 0) laid.push_back(s.laid_m / kMm);
  }
  return laid;
}

// A tool changer (or an IDEX printer) parks each tool with its filament drawn back and
// picks it up again, possibly many changes later, where that tool's next feed makes up
// its own retraction. The reader kept one retraction for all tools and cleared it at a
// change, so a file that does not prime in place after the pick-up laid the parked
// retraction as bead (T0's 2 mm and T1's 1.5 mm here: 14 mm of beads where 10.5 leave
// the nozzles). In both E forms: relative (M83) and absolute with "G92 E0" around the
// change (Cura's).
TEST(GcodeMultiTool, EachToolKeepsItsRetractionWhileParked) {
  const std::string relative =
      "M83\nG1 X0 Y0 Z0.2 F1200\nT0\nG1 X10 Y0 E5\nG1 E-2\nT1\nG1 X10 Y10 E3\nG1 E-1.5\nT0\n"
      "G1 X0 Y10 E4\nT1\nG1 X0 Y0 E2\n";
  const std::string absolute =
      "M82\nG92 E0\nG1 X0 Y0 Z0.2 F1200\nT0\nG1 X10 Y0 E5\nG1 E3\nG92 E0\nT1\nG92 E0\nG1 X10 Y10 E3\n"
      "G1 E1.5\nG92 E0\nT0\nG92 E0\nG1 X0 Y10 E4\nG92 E0\nT1\nG92 E0\nG1 X0 Y0 E2\n";
  for (const std::string& text : {relative, absolute}) {
    Toolpath p = ParseGcode(text, "changer.gcode");
    EXPECT_THAT(BeadsLaidMm(p), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{5, 3, 2, 0.5}))
        << text;
    EXPECT_NEAR(p.BeadFilamentLength(false) / kMm, 10.5, 1e-9);
    EXPECT_NEAR(p.BlobFilamentLength(false) / kMm, 0, 1e-12);
  }
  // A prime in place after the pick-up (Cura's, the QIDI i-Fast's "G1 F1200 E8.5")
  // still refills the nozzle, however long: no blob, no bead lost.
  Toolpath primed = ParseGcode(
      "M83\nG1 X0 Y0 Z0.2 F1200\nG1 X10 Y0 E5\nG1 E-8\nT1\nG1 E9\nG1 X10 Y10 E3\nG1 E-8\nT0\nG1 E8.5\n"
      "G1 X0 Y10 E4\n",
      "primed.gcode");
  EXPECT_THAT(BeadsLaidMm(primed), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{5, 3, 4}));
  EXPECT_NEAR(primed.BlobFilamentLength(false) / kMm, 0, 1e-12);
}

// A multi-material unit with one nozzle (PrusaSlicer's single-extruder multi-material
// tool change): the old filament is unloaded up the tube ("G1 E-90"), the new one
// loaded partly in place and partly while moving over the wipe tower ("; CP TOOLCHANGE
// LOAD": 20 % in place, 70 % and 10 % with X). When a filament unloaded earlier in the
// file is loaded again, its loading moves make up its unload and lay nothing (they laid
// 72 mm of bead on the tower before).
TEST(GcodeMultiTool, ReloadedFilamentMakesUpItsUnload) {
  const std::string load = "G1 E18 F3000\nG1 X40 Y0 E63\nG1 X30 Y0 E9\n";
  const std::string text = "M83\nG1 X0 Y0 Z0.2 F1200\nT0\nG1 X20 Y0 E4\nG1 E-90\nT1\n" + load +
                           "G1 X30 Y10 E2\nG1 E-90\nT0\n" + load + "G1 X30 Y20 E1\n";
  Toolpath p = ParseGcode(text, "mmu.gcode");
  // T1's first load: its filament's place before the file is the unit's (left: laid).
  EXPECT_THAT(BeadsLaidMm(p), ::testing::Pointwise(::testing::DoubleNear(1e-9),
                                                   std::vector<double>{4, 63, 9, 2, 0, 0, 1}));
  EXPECT_NEAR(p.BlobFilamentLength(false) / kMm, 0, 1e-12);
}

// Klipper's ACTIVATE_EXTRUDER EXTRUDER=extruder1 makes that extruder active, and its
// gcode_move sets the E base to the current position and the extrude factor to 1 on
// that event: absolute E restarts at 0 and M221's flow is 100 % again. It was skipped,
// so "E2" after "E5" was a retraction (-3 mm at 90 %), and the next bead made it up.
TEST(GcodeMultiTool, KlipperActivateExtruderRestartsEAndFlow) {
  Toolpath p = ParseGcode(
      "M82\nG92 E0\nG1 X0 Y0 Z0.2 F1200\nG1 X10 Y0 E5\nM221 S90\nACTIVATE_EXTRUDER EXTRUDER=extruder1\n"
      "G1 X10 Y10 E2\nG1 X0 Y10 E3\nACTIVATE_EXTRUDER EXTRUDER=extruder1\nG1 X0 Y0 E4\n"
      "ACTIVATE_EXTRUDER EXTRUDER=extruder\nG1 X10 Y0 E1\n",
      "klipper.gcode");
  // Activating the active extruder again changes nothing (Klipper: "already active").
  EXPECT_THAT(BeadsLaidMm(p), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{5, 2, 1, 1, 1}));
  for (const char* bad : {"ACTIVATE_EXTRUDER EXTRUDER=hotend2\n", "ACTIVATE_EXTRUDER\n",
                          "ACTIVATE_EXTRUDER EXTRUDER=extruder1x\n"}) {
    EXPECT_THAT(test::ErrorOf([&] { ParseGcode(std::string("G28\n") + bad, "bad.gcode"); }),
                HasSubstr("bad.gcode:2"))
        << bad;
  }
}

}  // namespace
}  // namespace lt

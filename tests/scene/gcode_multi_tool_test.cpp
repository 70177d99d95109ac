// Files that print with several tools (tool changers, IDEX printers, multi-material units,
// Klipper's extruders): each tool's filament drawn back, Klipper's ACTIVATE_EXTRUDER and
// T macros, firmware retraction per tool, a T on a MakerBot file's M104.
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

// Klipper has no T command: a Klipper file's "T1" runs the printer's macro, which calls
// ACTIVATE_EXTRUDER EXTRUDER=extruder1 (E restarts at 0, the flow is 100 %). It was read
// as Marlin's T (E goes on from 5, M221's 90 % of tool 0 not applying to tool 1): "E2"
// after "E5" was a 3 mm retraction and the next beads made it up. A file is Klipper's
// by its flavour comment (anywhere: PrusaSlicer's config block ends the file) or by one
// of Klipper's own commands before the T; otherwise T is Marlin's, as before.
TEST(GcodeMultiTool, KlipperTMacroActivatesItsExtruder) {
  const std::string body =
      "M82\nG92 E0\nG1 X0 Y0 Z0.2 F1200\nG1 X10 Y0 E5\nM221 S90\nT1\nG1 X10 Y10 E2\nG1 X0 Y10 E3\nT1\n"
      "G1 X0 Y0 E4\nT0\nG1 X10 Y0 E1\n";
  for (const std::string& text : {";FLAVOR:Klipper\n" + body, "SET_VELOCITY_LIMIT ACCEL=3000\n" + body,
                                  body + "; prusaslicer_config = begin\n; gcode_flavor = klipper\n"}) {
    Toolpath p = ParseGcode(text, "klipper.gcode");
    EXPECT_THAT(BeadsLaidMm(p), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{5, 2, 1, 1, 1}))
        << text;
    ASSERT_EQ(p.warnings.size(), 1u) << text;
    EXPECT_EQ(p.warnings[0].count, 2);  // the changes (T1 again is no change)
    EXPECT_THAT(p.warnings[0].text, HasSubstr("T1 in a Klipper file is a macro"));
    EXPECT_THAT(p.warnings[0].text, HasSubstr("ACTIVATE_EXTRUDER EXTRUDER=extruder1"));
  }
  // Marlin's T: one E position for all tools (E2 after E5 draws back 3 mm, which E3 and
  // E4 make up in part; back on T0, E1 draws back 2.7 mm at 90 %), no warning.
  Toolpath marlin = ParseGcode(body, "marlin.gcode");
  EXPECT_THAT(BeadsLaidMm(marlin), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{5, 0, 0}));
  EXPECT_TRUE(marlin.warnings.empty());
}

// The filament fed by the segments a command wrote (gcode 10 or 11), in order (mm).
std::vector<double> FirmwareFeedsMm(const Toolpath& p, int gcode) {
  std::vector<double> fed;
  for (const ToolpathSegment& s : p.segments) {
    if (s.gcode == gcode && s.extruded_m != 0) fed.push_back(s.extruded_m / kMm);
  }
  return fed;
}

// Firmware retraction keeps its state per tool, as Marlin (retracted[active_extruder])
// and RepRapFirmware (per tool) do: T1's G10 retracts T1 though T0 is retracted, and
// back on T0 its G11 recovers T0's. The reader kept one state: T1's G10 did nothing,
// T0's G11 did nothing, and T0's next bead made up its 2 mm (beads 5, 3, 2 where 12 mm
// leave the nozzles). Klipper's firmware_retraction keeps one state, and so does the
// reader for a Klipper file. The Z hop is one for the machine (Marlin's current_hop).
TEST(GcodeMultiTool, FirmwareRetractionIsKeptPerTool) {
  const std::string body = "M83\nG1 X0 Y0 Z0.2 F1200\nM207 S2 F1800 Z0.4\nG1 X10 Y0 E5\nG10\nT1\nG10\n"
                           "G1 X10 Y10\nG11\nG1 X0 Y10 E3\nT0\nG11\nG1 X0 Y0 E4\n";
  Toolpath p = ParseGcode(body, "fw.gcode");
  EXPECT_THAT(BeadsLaidMm(p), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{5, 3, 4}));
  EXPECT_THAT(FirmwareFeedsMm(p, 10), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{-2, -2}));
  EXPECT_THAT(FirmwareFeedsMm(p, 11), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{2, 2}));
  EXPECT_NEAR(p.BlobFilamentLength(false) / kMm, 0, 1e-12);
  EXPECT_NEAR(p.segments.back().end_m.z() / kMm, 0.2, 1e-9);  // lifted once, lowered once
  // RepRapFirmware's M207 P: one tool's settings ("M207 P1 S0.8", a tool changer's
  // filament macro); it was "M207 takes no parameter P".
  Toolpath rrf = ParseGcode("M83\nG1 X0 Y0 Z0.2 F1200\nM207 S2\nM207 P1 S0.8 F1200\nG10\nG11\nT1\nG10\nG11\n",
                            "rrf.gcode");
  EXPECT_THAT(FirmwareFeedsMm(rrf, 10), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{-2, -0.8}));
  // Klipper: one state (T1's G10 does nothing while T0 is retracted).
  Toolpath klipper = ParseGcode(";FLAVOR:Klipper\n" + body, "k.gcode");
  EXPECT_THAT(FirmwareFeedsMm(klipper, 10), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{-2}));
  EXPECT_THAT(FirmwareFeedsMm(klipper, 11), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{2}));
}

// Marlin's "G10 S1" (multi-extruder) is the swap retraction before a tool swap: M207 W's
// length (13 mm by default), recovered by that tool's next G11 with M208 W's extra at
// M208 R's feed. It was skipped as a G10 with parameters, and the G11 did nothing.
TEST(GcodeMultiTool, MarlinSwapRetractionIsRecoveredByG11) {
  Toolpath p = ParseGcode("M83\nG1 X0 Y0 Z0.2 F1200\nM207 S2 W20\nM208 W1 R600\nG1 X10 Y0 E5\nG10 S1\nT1\n"
                          "G1 X10 Y10 E3\nT0\nG11\nG1 X0 Y0 E4\nG10 S1\nG11\n",
                          "swap.gcode");
  EXPECT_THAT(FirmwareFeedsMm(p, 10), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{-20, -20}));
  EXPECT_THAT(FirmwareFeedsMm(p, 11), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{21, 21}));
  for (const ToolpathSegment& s : p.segments) {
    if (s.gcode == 11) EXPECT_NEAR(s.t_end_s - s.t_start_s, 2.1, 1e-9);  // 21 mm at 10 mm/s
  }
  EXPECT_THAT(BeadsLaidMm(p), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{5, 3, 4}));
  EXPECT_EQ(p.skipped_commands.count("G10"), 0u);
}

// GPX reads "M104 S220 T1" as tool 1's temperature, the active tool unchanged (only T,
// M6 T and M135 T change it); ReplicatorG on a dual-extruder machine makes T1 active, so
// in a MakerBot file (E the active tool's axis, A or B) the two feed different axes. Read
// as GPX, and warned (it was silent).
TEST(GcodeMultiTool, MakerBotTemperatureForAnotherToolIsWarned) {
  Toolpath p = ParseGcode("G92 X0 Y0 Z0 A0 B0\nM135 T0\nG1 X0 Y0 Z0.2 F1200\nG1 X10 Y0 A1\nM104 S220 T1\n"
                          "M104 S220 T0\nG1 X10 Y10 E2\nM109 S220 T1\n",
                          "makerbot.gcode");
  EXPECT_THAT(BeadsLaidMm(p), ::testing::Pointwise(::testing::DoubleNear(1e-9), std::vector<double>{1, 1}));
  const ToolpathWarning* tool_word = nullptr;
  for (const ToolpathWarning& w : p.warnings) {
    if (w.text.find("GPX") != std::string::npos) tool_word = &w;
  }
  ASSERT_NE(tool_word, nullptr);
  EXPECT_EQ(tool_word->line, 5);
  EXPECT_EQ(tool_word->count, 2);  // M104 T1, M109 T1 (T0 is the active tool)
  EXPECT_THAT(tool_word->text, HasSubstr("M104 T1: the tool the command is for"));
  // In a file that prints with E alone (Marlin's reading), M104 T1 is a temperature only.
  Toolpath marlin = ParseGcode("G1 X0 Y0 Z0.2 F1200\nM104 S220 T1\nG1 X10 Y0 E1\n", "marlin.gcode");
  EXPECT_TRUE(marlin.warnings.empty());
}

}  // namespace
}  // namespace lt

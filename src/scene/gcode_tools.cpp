// The G-code reader's tools: the active tool, each tool's filament drawn back
// (retraction pending per tool), Klipper's ACTIVATE_EXTRUDER and T macros, a T on
// another M command in MakerBot's G-code.
#include <algorithm>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/text_fields.h"
#include "scene/gcode_reader.h"

namespace lt {
namespace gcode_detail {

void GcodeReader::SelectTool(int n) {
  if (n < 0 || n == active_tool_) return;  // RepRapFirmware's T-1 deselects: no tool's settings change
  // Each tool's filament is its own: what the old tool drew back before it was parked
  // stays drawn back in its nozzle (a tool changer's or an IDEX printer's parked tool;
  // an MMU's unloaded filament) until that tool feeds again, possibly many changes
  // later; the new tool takes up its own (none if it has not fed yet in the file). Marlin
  // keeps its firmware retraction per extruder too (FWRETRACT's retracted[active_extruder]).
  parked_retraction_mm_[active_tool_] = retracted_mm_;
  active_tool_ = n;  // the tool whose flow (M221) applies and whose axis E is (ExtruderSlot)
  const auto parked = parked_retraction_mm_.find(n);
  retracted_mm_ = parked == parked_retraction_mm_.end() ? 0 : parked->second;
  // What the firmware or the tool changer does at the change (Marlin's swap retraction
  // and prime, a tool changer's macros, an MMU's load) is the printer's and not in the
  // file, so the feeds in place before the tool's first bead refill its nozzle: no blob
  // ("T0 / G1 F1200 E8.5", the slicer's prime of a parked nozzle).
  new_tool_unprimed_ = true;
}

void GcodeReader::KlipperActivateExtruder(std::string_view params) {
  // Klipper's ACTIVATE_EXTRUDER EXTRUDER=extruder1 (the extruders are named "extruder",
  // "extruder1", ...; another name is an error there too). Activating another extruder
  // raises Klipper's "extruder:activate_extruder" event, on which gcode_move sets its
  // E base to the current position and its extrude factor to 1: the file's E restarts
  // at 0 (as after "G92 E0") and M221's flow is back at 100 %. The active one again:
  // nothing ("Extruder ... already active").
  std::optional<int> tool;
  std::string given;
  for (const auto& [key, text] : KeyValues(params)) {
    if (key != "EXTRUDER") continue;
    given = std::string(text);
    const std::string lower = Lower(given);
    const std::string_view digits = std::string_view(lower).substr(std::min<size_t>(8, lower.size()));
    if (!StartsWith(lower, "extruder") || digits.size() > 6 ||
        digits.find_first_not_of("0123456789") != std::string_view::npos) {
      tool.reset();
      break;
    }
    tool = digits.empty() ? 0 : std::stoi(std::string(digits));
  }
  if (!tool) {
    Fail("ACTIVATE_EXTRUDER needs EXTRUDER= naming an extruder (\"extruder\", \"extruder1\", ...), got \"" +
         given + "\"");
  }
  ActivateKlipperExtruder(*tool);
}

void GcodeReader::ActivateKlipperExtruder(int tool) {
  if (tool == active_tool_) return;
  SelectTool(tool);
  e_logical_mm_[ExtruderSlot(0)] = 0;
  flow_factor_.clear();
}

void GcodeReader::KlipperToolMacro(int n) {
  // Klipper has no T command: a file's "T1" runs the printer's [gcode_macro T1], which
  // on a multi-extruder printer calls ACTIVATE_EXTRUDER EXTRUDER=extruder1 (Klipper's
  // sample configurations and the usual toolchanger and IDEX macros do), beside what
  // the macro moves (a park, a dock) and sets (offsets, temperatures).
  if (n < 0 || n == active_tool_) return;  // the active extruder again: Klipper does nothing
  const std::string extruder = n == 0 ? "extruder" : "extruder" + std::to_string(n);
  WarnOncePerName("Klipper T", "T" + std::to_string(n) + " in a Klipper file is a macro of the printer's "
                  "configuration, read as the ACTIVATE_EXTRUDER EXTRUDER=" + extruder + " it usually calls (E "
                  "restarts at 0, the flow is 100 %); whatever else it does (parking, moves, offsets) is not in the "
                  "toolpath or its times");
  ActivateKlipperExtruder(n);
}

void GcodeReader::ToolWordOnMCommand(const std::string& command, std::optional<double> tool) {
  // GPX (MakerBot's and Sailfish's G-code to x3g): "M104 S220 T1" sets tool 1's
  // temperature, M106/M107/M126/M127 T1 its fans, M109 T1 its platform; only T n,
  // M6 T n and M135 T n change the tool. ReplicatorG on a dual-extruder machine takes
  // the T of any M command as a tool selection (its E then goes to that tool's axis).
  // Read as GPX; warned where the two differ (a T other than the active tool).
  if (extruder_axes_ != ExtruderAxes::kEIsActiveAB || !tool || *tool == active_tool_) return;
  WarnOncePerName("M command T", command + " T" + FormatNumber(*tool) + ": the tool the command is for, read "
                  "as GPX reads it (the active tool stays T" + std::to_string(active_tool_) + ", E on its axis); "
                  "ReplicatorG on a dual-extruder machine makes it the active tool, so E would feed the other axis");
}

}  // namespace gcode_detail
}  // namespace lt

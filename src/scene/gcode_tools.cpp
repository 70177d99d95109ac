// The G-code reader's tools: the active tool, each tool's filament drawn back
// (retraction pending per tool), Klipper's ACTIVATE_EXTRUDER.
#include <algorithm>
#include <optional>
#include <string>
#include <string_view>

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
  if (*tool == active_tool_) return;
  SelectTool(*tool);
  e_logical_mm_[ExtruderSlot(0)] = 0;
  flow_factor_.clear();
}

}  // namespace gcode_detail
}  // namespace lt

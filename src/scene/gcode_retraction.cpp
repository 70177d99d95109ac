// The G-code reader's firmware retraction: G10 retracts and G11 recovers the
// filament (with the Z hop), by the length and feed rates M207 sets.
#include <cmath>
#include <optional>
#include <string>

#include "core/error.h"
#include "scene/gcode_reader.h"
#include "core/text_fields.h"

namespace lt {
namespace gcode_detail {

GcodeReader::FwRetraction& GcodeReader::FwSettings(std::optional<int> tool) {
  if (!tool) return fw_;
  const auto own = fw_of_tool_.find(*tool);
  return own == fw_of_tool_.end() ? fw_ : own->second;
}

void GcodeReader::FirmwareRetract(bool retract, bool swap) {
  ++(retract ? path_.firmware_retractions : path_.firmware_recoveries);
  if (retract && swap) ++path_.swap_retractions;
  if (path_.firmware_retractions + path_.firmware_recoveries == 1) path_.first_firmware_retraction_line = line_no_;
  // Marlin keeps whether each extruder is retracted (retracted[active_extruder]), and
  // so does RepRapFirmware (per tool): a G10 after a tool change retracts the new tool
  // though the old one is retracted, and its G11 recovers the new tool's only. Klipper
  // keeps one state (FwStateKey). The firmware ignores a second G10 (or G11) of a tool.
  int& state = fw_state_[FwStateKey()];
  if (retract == (state != 0)) return;
  // A G11 recovers what that tool's G10 drew back: the swap's length after G10 S1.
  const bool swapped = retract ? swap : state == 2;
  state = retract ? (swapped ? 2 : 1) : 0;
  const FwRetraction& fw = FwSettings(klipper_ ? std::nullopt : std::optional<int>(active_tool_));
  const double length = swapped ? fw.swap_length_mm : fw.length_mm;
  if (retract) {
    AddSegment(10, pos_mm_, -length, 0, 0, nullptr, fw.feed_mm_s);
    if (fw.hop_mm > 0 && fw_hop_applied_mm_ == 0) {
      Eigen::Vector3d up = pos_mm_ + Eigen::Vector3d(0, 0, fw.hop_mm);
      AddSegment(10, up, 0, fw.hop_mm, 0, nullptr, fw.feed_mm_s);
      offset_mm_.z() += fw.hop_mm;  // logical Z unchanged: later Z moves stay lifted
      fw_hop_applied_mm_ = fw.hop_mm;
    }
  } else {
    if (fw_hop_applied_mm_ > 0) {
      Eigen::Vector3d down = pos_mm_ - Eigen::Vector3d(0, 0, fw_hop_applied_mm_);
      AddSegment(11, down, 0, fw_hop_applied_mm_, 0, nullptr, fw.feed_mm_s);
      offset_mm_.z() -= fw_hop_applied_mm_;
      fw_hop_applied_mm_ = 0;
    }
    const double extra = swapped ? fw.swap_recover_extra_mm : fw.recover_extra_mm;
    AddSegment(11, pos_mm_, length + extra, 0, 0, nullptr, swapped ? fw.swap_recover_feed_mm_s : fw.recover_feed_mm_s);
  }
}

void GcodeReader::RetractSettings() {
  // M207 S length, F feed (mm/min), Z hop (Marlin and RepRapFirmware); R extra length
  // and T feed (mm/min) on recovery (RepRapFirmware); W the swap retraction's length
  // (Marlin); P the tool whose settings these are (RepRapFirmware: "M207 P1 S0.8",
  // a tool changer's filament macros), else every tool's.
  Expect("SFZRTWP", "M207");
  std::optional<int> tool;
  if (const Word* p = Find('P')) {
    if (*p->value < 0 || *p->value >= 1e6 || *p->value != std::floor(*p->value)) {
      Fail("M207 P must be a tool number, got " + FormatNumber(*p->value));
    }
    tool = int(*p->value);
    if (!fw_of_tool_.count(*tool)) fw_of_tool_[*tool] = fw_;
  } else {
    fw_of_tool_.clear();  // every tool's
  }
  FwRetraction& fw = FwSettings(tool);
  auto length = [&](char letter, double& out) {
    if (const Word* w = Find(letter)) {
      if (*w->value < 0) Fail(std::string("M207 ") + letter + " must be >= 0, got " + FormatNumber(*w->value));
      out = *w->value * unit_mm_;
    }
  };
  auto feed = [&](char letter, double& out) {
    if (const Word* w = Find(letter)) {
      if (!(*w->value > 0)) Fail(std::string("M207 ") + letter + " (feed rate) must be > 0, got " + FormatNumber(*w->value));
      out = *w->value * unit_mm_ / 60.0;
    }
  };
  length('S', fw.length_mm);
  length('Z', fw.hop_mm);
  length('R', fw.recover_extra_mm);
  length('W', fw.swap_length_mm);
  feed('F', fw.feed_mm_s);
  if (Find('F') && !Find('T')) fw.recover_feed_mm_s = fw.feed_mm_s;  // RepRapFirmware: T defaults to F
  feed('T', fw.recover_feed_mm_s);
  path_.firmware_retraction_set = true;
}

void GcodeReader::KlipperRetractSettings(std::string_view params) {
  // Klipper's values are millimetres and mm/s whatever G20 says; other keys are ignored
  // as Klipper ignores them.
  struct Key {
    const char* name;
    double* value;
    bool speed;
  };
  const Key keys[] = {{"RETRACT_LENGTH", &fw_.length_mm, false},
                      {"RETRACT_SPEED", &fw_.feed_mm_s, true},
                      {"UNRETRACT_EXTRA_LENGTH", &fw_.recover_extra_mm, false},
                      {"UNRETRACT_SPEED", &fw_.recover_feed_mm_s, true},
                      {"Z_HOP_HEIGHT", &fw_.hop_mm, false}};
  for (const auto& [key, text] : KeyValues(params)) {
    for (const Key& k : keys) {
      if (key != k.name) continue;
      auto v = ParseFiniteNumber(text);
      if (!v || (k.speed ? !(*v > 0) : *v < 0)) {
        Fail("SET_RETRACTION " + key + " must be a number " + (k.speed ? "> 0" : ">= 0") + ", got \"" +
             std::string(text) + "\"");
      }
      *k.value = *v;
    }
  }
  path_.firmware_retraction_set = true;
}

void GcodeReader::RecoverSettings() {
  // Marlin's M208: S extra length on recovery, F its feed (mm/min); W and R the same
  // for the swap retraction (G10 S1). (RepRapFirmware's M208, axis limits, is skipped
  // before.)
  Expect("SFRW", "M208");
  auto length = [&](char letter, double& out) {
    if (const Word* w = Find(letter)) {
      if (*w->value < 0) Fail(std::string("M208 ") + letter + " (extra length on recovery) must be >= 0, got " + FormatNumber(*w->value));
      out = *w->value * unit_mm_;
    }
  };
  auto feed = [&](char letter, double& out) {
    if (const Word* w = Find(letter)) {
      if (!(*w->value > 0)) Fail(std::string("M208 ") + letter + " (recovery feed rate) must be > 0, got " + FormatNumber(*w->value));
      out = *w->value * unit_mm_ / 60.0;
    }
  };
  length('S', fw_.recover_extra_mm);
  length('W', fw_.swap_recover_extra_mm);
  feed('F', fw_.recover_feed_mm_s);
  feed('R', fw_.swap_recover_feed_mm_s);
  path_.firmware_retraction_set = true;
}

}  // namespace gcode_detail
}  // namespace lt

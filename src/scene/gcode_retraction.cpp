// The G-code reader's firmware retraction: G10 retracts and G11 recovers the
// filament (with the Z hop), by the length and feed rates M207 sets.
#include <string>

#include "core/error.h"
#include "scene/gcode_reader.h"
#include "core/text_fields.h"

namespace lt {
namespace gcode_detail {

void GcodeReader::FirmwareRetract(bool retract) {
  ++(retract ? path_.firmware_retractions : path_.firmware_recoveries);
  if (path_.firmware_retractions + path_.firmware_recoveries == 1) path_.first_firmware_retraction_line = line_no_;
  if (retract == fw_retracted_) return;  // the firmware ignores a second G10 (or G11)
  fw_retracted_ = retract;
  if (retract) {
    AddSegment(10, pos_mm_, -fw_retract_mm_, 0, 0, nullptr, fw_retract_feed_mm_s_);
    if (fw_hop_mm_ > 0) {
      Eigen::Vector3d up = pos_mm_ + Eigen::Vector3d(0, 0, fw_hop_mm_);
      AddSegment(10, up, 0, fw_hop_mm_, 0, nullptr, fw_retract_feed_mm_s_);
      offset_mm_.z() += fw_hop_mm_;  // logical Z unchanged: later Z moves stay lifted
      fw_hop_applied_mm_ = fw_hop_mm_;
    }
  } else {
    if (fw_hop_applied_mm_ > 0) {
      Eigen::Vector3d down = pos_mm_ - Eigen::Vector3d(0, 0, fw_hop_applied_mm_);
      AddSegment(11, down, 0, fw_hop_applied_mm_, 0, nullptr, fw_retract_feed_mm_s_);
      offset_mm_.z() -= fw_hop_applied_mm_;
      fw_hop_applied_mm_ = 0;
    }
    AddSegment(11, pos_mm_, fw_retract_mm_ + fw_recover_extra_mm_, 0, 0, nullptr, fw_recover_feed_mm_s_);
  }
}

void GcodeReader::RetractSettings() {
  // M207 S length, F feed (mm/min), Z hop (Marlin and RepRapFirmware); R extra length
  // and T feed (mm/min) on recovery (RepRapFirmware); W swap length (Marlin, not used).
  Expect("SFZRTW", "M207");
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
  length('S', fw_retract_mm_);
  length('Z', fw_hop_mm_);
  length('R', fw_recover_extra_mm_);
  feed('F', fw_retract_feed_mm_s_);
  if (Find('F') && !Find('T')) fw_recover_feed_mm_s_ = fw_retract_feed_mm_s_;  // RepRapFirmware: T defaults to F
  feed('T', fw_recover_feed_mm_s_);
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
  const Key keys[] = {{"RETRACT_LENGTH", &fw_retract_mm_, false},
                      {"RETRACT_SPEED", &fw_retract_feed_mm_s_, true},
                      {"UNRETRACT_EXTRA_LENGTH", &fw_recover_extra_mm_, false},
                      {"UNRETRACT_SPEED", &fw_recover_feed_mm_s_, true},
                      {"Z_HOP_HEIGHT", &fw_hop_mm_, false}};
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
  // Marlin's M208: S extra length on recovery, F its feed (mm/min); R and W are the
  // tool swap's (not used). (RepRapFirmware's M208, axis limits, is skipped before.)
  Expect("SFR", "M208");
  if (const Word* s = Find('S')) {
    if (*s->value < 0) Fail("M208 S (extra length on recovery) must be >= 0, got " + FormatNumber(*s->value));
    fw_recover_extra_mm_ = *s->value * unit_mm_;
  }
  if (const Word* f = Find('F')) {
    if (!(*f->value > 0)) Fail("M208 F (recovery feed rate) must be > 0, got " + FormatNumber(*f->value));
    fw_recover_feed_mm_s_ = *f->value * unit_mm_ / 60.0;
  }
  path_.firmware_retraction_set = true;
}

}  // namespace gcode_detail
}  // namespace lt

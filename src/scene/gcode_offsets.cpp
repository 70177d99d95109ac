// The G-code reader's offsets between the file's coordinates and the machine's: G92
// and its resets (G92.1-G92.3), work coordinate systems (G54-G59.3, set by G10 L2 and
// L20), machine coordinates for one line (G53, in scene/gcode_moves.cpp's Target),
// babystepping (M290), Bambu's z-trim (G29.1 Z), and what homing clears.
//
// The machine position is the logical one plus offset_mm_, the sum of G92's offset,
// the active work system's, Klipper's SET_GCODE_OFFSET, Bambu's z-trim, babystepping
// and a firmware retraction's Z hop. G92's is kept apart from the work offsets, as LinuxCNC does
// (RepRapFirmware and Marlin fold G92 into the active work system's offset: the two
// differ only when a file changes work systems after a G92 on X, Y or Z).
#include <cmath>
#include <string>

#include "core/error.h"
#include "scene/gcode_reader.h"

namespace lt {
namespace gcode_detail {

Eigen::Vector3d GcodeReader::PhysicalOffset() const {
  return Eigen::Vector3d(klipper_offset_mm_[0], klipper_offset_mm_[1],
                         klipper_offset_mm_[2] + z_trim_mm_ + fw_hop_applied_mm_) +
         babystep_mm_;
}

void GcodeReader::ZTrim(double z_mm) {
  offset_mm_.z() += z_mm - z_trim_mm_;  // later absolute moves; the nozzle moves with the next one
  z_trim_mm_ = z_mm;
}

void GcodeReader::HomeAxis(int k) {
  babystep_mm_[k] = 0;  // the endstop finds the axis where it is: the babysteps are gone
  offset_mm_[k] = OffsetWithoutG92()[k];
  axis_known_[k] = true;
}

void GcodeReader::HomeToEndstops(const std::string& command, bool homing) {
  const char axes[3] = {'X', 'Y', 'Z'};
  std::string named;
  for (int k = 0; k < 3; ++k) {
    if (Find(axes[k])) named += axes[k];
  }
  if (named.empty()) named = "XYZ";
  for (char a : named) {
    const int k = a - 'X';
    if (homing) babystep_mm_[k] = 0;
    offset_mm_[k] = OffsetWithoutG92()[k];  // the firmware's coordinates from here on, G92's gone
    axis_known_[k] = false;
  }
  unknown_since_ = command + " (line " + std::to_string(line_no_) + ")";
  std::string list;
  for (char a : named) list += std::string(list.empty() ? "" : " ") + a;
  WarnOncePerName(command, command + (homing ? " homes " + list + " to the endstops" : " recalls the home offsets of " + list +
                                          " stored in the printer") +
                               " (MakerBot, Sailfish): where that puts the nozzle is the printer's configuration, so " +
                               list + (named.size() == 1 ? " stays" : " stay") + " unknown until G92 or an absolute move sets them" +
                               (homing ? "; the homing takes no time in the toolpath" : ""));
}

void GcodeReader::SetPosition() {
  Expect("XYZEABUVWC", "G92");
  if (words_.empty()) {
    offset_mm_ = pos_mm_;
    for (int k = 0; k < 3; ++k) {
      if (axis_known_[k]) continue;
      offset_mm_[k] = OffsetWithoutG92()[k];  // as a named axis below: the nozzle is at 0
      pos_mm_[k] = offset_mm_[k];
      axis_known_[k] = true;
    }
    for (double& e : e_logical_mm_) e = 0;
    for (double& a : extra_axes_) a = 0;
    return;
  }
  ExtraAxes("G92", 0, ExtraAxesUse::kSet);
  const char axes[3] = {'X', 'Y', 'Z'};
  for (int k = 0; k < 3; ++k) {
    const Word* w = Find(axes[k]);
    if (!w) continue;
    // On an axis whose place is unknown (homed to an endstop of the printer's
    // configuration: MakerBot's "G162 Z" then "G92 Z80"), G92 states where the nozzle
    // is rather than shifting a known frame: no G92 offset, and the axis is known again
    // there (a relative move goes on from it).
    if (axis_known_[k]) {
      offset_mm_[k] = pos_mm_[k] - *w->value * unit_mm_;
    } else {
      offset_mm_[k] = OffsetWithoutG92()[k];
      pos_mm_[k] = *w->value * unit_mm_ + offset_mm_[k];
      axis_known_[k] = true;
    }
  }
  const char letters[3] = {'E', 'A', 'B'};
  for (int k = 0; k < (ABAreExtruders() ? 3 : 1); ++k) {
    if (const Word* e = Find(letters[k])) e_logical_mm_[ExtruderSlot(k)] = *e->value * unit_mm_;
  }
}

void GcodeReader::ResetPosition(int variant) {
  const std::string command = "G92." + std::to_string(variant);
  Expect("", command);
  if (variant == 3) {
    offset_mm_ = OffsetWithoutG92() + saved_g92_mm_;
    return;
  }
  if (variant == 2) saved_g92_mm_ = offset_mm_ - OffsetWithoutG92();
  offset_mm_ = OffsetWithoutG92();
}

void GcodeReader::SelectWorkSystem(int index) {
  offset_mm_ += work_offset_mm_[index] - work_offset_mm_[work_system_];
  work_system_ = index;
}

void GcodeReader::SetWorkOffset(int l) {
  const std::string command = "G10 L" + std::to_string(l);
  Expect("LPXYZ", command);
  int index = work_system_;  // P0 or no P: the active system
  if (const Word* p = Find('P')) {
    if (*p->value < 0 || *p->value > 9 || *p->value != std::floor(*p->value)) {  // range first: int() of 1e20 is UB
      Fail(command + " P must be a coordinate system 1-9 (G54-G59.3) or 0 (the active one), got " +
           FormatNumber(*p->value));
    }
    if (*p->value > 0) index = int(*p->value) - 1;
  }
  const char axes[3] = {'X', 'Y', 'Z'};
  for (int k = 0; k < 3; ++k) {
    const Word* w = Find(axes[k]);
    if (!w) continue;
    const double v = *w->value * unit_mm_;
    // L2: the system's origin in machine coordinates; L20: the origin that makes the
    // current position v in that system (the other offsets as they are).
    const double origin = l == 2 ? v : pos_mm_[k] - v - (offset_mm_[k] - work_offset_mm_[work_system_][k]);
    if (index == work_system_) offset_mm_[k] += origin - work_offset_mm_[index][k];
    work_offset_mm_[index][k] = origin;
  }
}

void GcodeReader::Babystep() {
  // Marlin: X, Y, Z (S is Z), P (also the probe's offset: no motion of its own);
  // RepRapFirmware: S or Z, R1 relative (the default) or R0 absolute.
  Expect("XYZSPR", "M290");
  if (Find('S') && Find('Z')) Fail("M290 takes S or Z, not both");
  const Word* r = Find('R');
  if (r && *r->value != 0 && *r->value != 1) {
    Fail("M290 R must be 0 (absolute) or 1 (relative), got " + FormatNumber(*r->value));
  }
  const bool absolute = r && *r->value == 0;
  Eigen::Vector3d step = Eigen::Vector3d::Zero();
  const char axes[3] = {'X', 'Y', 'Z'};
  for (int k = 0; k < 3; ++k) {
    const Word* w = Find(axes[k]);
    if (k == 2 && !w) w = Find('S');
    if (w) step[k] = *w->value * unit_mm_ - (absolute ? babystep_mm_[k] : 0.0);
  }
  babystep_mm_ += step;
  offset_mm_ += step;  // later moves land that much further
  const Eigen::Vector3d end = pos_mm_ + step;
  AddSegment(1, end, 0, step.norm(), step.head<2>().norm(), nullptr, MoveFeed(step.norm(), 0));
}

}  // namespace gcode_detail
}  // namespace lt

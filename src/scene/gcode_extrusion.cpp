// The G-code reader's extruder words: the filament a move's E (or A, B) feeds, in
// absolute or relative mode, by volume under M200, scaled by each tool's M221 flow.
#include <cmath>
#include <string>

#include "core/error.h"
#include "scene/gcode_reader.h"

namespace lt {
namespace gcode_detail {

double GcodeReader::Extruded() {
  const Word* e = nullptr;
  int axis = -1;
  const char letters[3] = {'E', 'A', 'B'};
  for (int k = 0; k < (ABAreExtruders() ? 3 : 1); ++k) {
    if (const Word* w = Find(letters[k])) {
      // A 5-axis printer's file turns rotary A, B (and C) axes while E extrudes: say so.
      if (e) {
        Fail(std::string("both ") + letters[axis] + " and " + letters[k] +
             ": one extruder axis per move (A and B are read as extruders, as the Mach3 and Machinekit flavours "
             "and MakerBot's second extruder use them; rotary A/B axes of a 5-axis printer are not modelled)");
      }
      e = w;
      axis = k;
    }
  }
  if (!e) return 0;
  if (axis == 0 && extruder_axes_ == ExtruderAxes::kEIsActiveAB) {
    Warn(kEAsActiveAB, "E read as the active tool's axis, A (T0) or B (T1), sharing its position as MakerBot's "
                       "firmware reads it, since the file prints with A or B and gives E on moves too");
  }
  double v = *e->value * unit_mm_;
  double& logical = e_logical_mm_[ExtruderSlot(axis)];
  double delta = ERelative() ? v : v - logical;
  logical = ERelative() ? logical + v : v;
  // Volumetric: mm^3 of filament, as the length of the M200 diameter's filament.
  if (volumetric_ && volumetric_diameter_mm_ > 0) delta /= M_PI * 0.25 * volumetric_diameter_mm_ * volumetric_diameter_mm_;
  // M221's flow percentage scales what the motor feeds (retractions too, as Marlin's
  // e_factor does), not the logical E.
  const auto flow = flow_factor_.find(active_tool_);
  return flow == flow_factor_.end() ? delta : delta * flow->second;
}

void GcodeReader::VolumetricExtrusion() {
  // Marlin's and RepRapFirmware's M200: D the filament diameter (mm; D0 turns volumetric
  // extrusion off), S0/S1 off/on with the last diameter; T the extruder (all alike here).
  Expect("DSTL", "M200");
  if (const Word* d = Find('D')) {
    if (*d->value < 0) Fail("M200 D (filament diameter) must be >= 0, got " + FormatNumber(*d->value));
    // As Marlin: D0 turns it off and keeps the diameter for a later S1.
    if (*d->value > 0) volumetric_diameter_mm_ = *d->value * unit_mm_;
    volumetric_ = *d->value > 0;
  }
  if (const Word* on = Find('S')) volumetric_ = *on->value != 0 && !(Find('D') && *Find('D')->value == 0);
  // The part's beads take the filament's volume: the diameter the lengths are of.
  if (volumetric_ && volumetric_diameter_mm_ > 0) path_.filament_diameter_m = volumetric_diameter_mm_ * kMetresPerMm;
}

void GcodeReader::FlowFactor() {
  // T (Marlin) or D (RepRapFirmware's drive, taken as the tool) picks the extruder,
  // else the active tool's.
  Expect("STD", "M221");
  int tool = active_tool_;
  for (char letter : {'T', 'D'}) {
    if (const Word* w = Find(letter)) {
      // At most the largest command number read (ReadCommand's 1e6): int() of more is UB.
      if (!w->value || *w->value < 0 || *w->value >= 1e6 || *w->value != std::floor(*w->value)) {
        Fail(std::string("M221 ") + letter + " must be a tool number");
      }
      tool = int(*w->value);
    }
  }
  if (const Word* s = Find('S')) {
    if (!s->value || !(*s->value >= 0)) Fail("M221 S (flow percentage) must be >= 0");
    flow_factor_[tool] = *s->value / 100.0;
  }
}

}  // namespace gcode_detail
}  // namespace lt

// Toolpaths from G-code text and their orientation under a rule, for the tests of
// scene/caster.h.
#pragma once

#include <memory>
#include <string>

#include "scene/caster.h"
#include "scene/gcode.h"

namespace lt::orientation_test {

constexpr double kMm = 1e-3;

inline std::shared_ptr<const Toolpath> Path(const std::string& gcode) {
  return std::make_shared<const Toolpath>(ParseGcode(gcode, "test.gcode"));
}

// The rule with its length (the caster's window and the trailing wheel's trail) in mm.
inline ToolpathOrientation Orientation(std::shared_ptr<const Toolpath> path, OrientationMode mode,
                                       double length_mm = 10) {
  OrientationOptions o;
  o.mode = mode;
  o.caster_window_m = length_mm * kMm;
  o.trail_m = length_mm * kMm;
  return ToolpathOrientation(std::move(path), o);
}

}  // namespace lt::orientation_test

// The G-code reader's extended commands: a line whose command is a name (Klipper's
// commands and a printer's macros: PRINT_START, SET_RETRACTION, EXCLUDE_OBJECT_START
// NAME=...) or a command to the host ("@pause").
#include <string>
#include <string_view>

#include "scene/gcode_reader.h"

namespace lt {
namespace gcode_detail {

namespace {

// Klipper's probing and levelling commands (the names its documentation gives): the
// toolhead ends where the probing stops.
bool IsProbingMacro(const std::string& name) {
  for (const char* probing : {"BED_MESH_CALIBRATE", "QUAD_GANTRY_LEVEL", "Z_TILT_ADJUST", "SCREWS_TILT_CALCULATE",
                              "PROBE", "PROBE_ACCURACY", "DELTA_CALIBRATE", "BED_TILT_CALIBRATE"}) {
    if (name == probing) return true;
  }
  return false;
}

// Klipper's own commands that neither move the toolhead nor change how the file's
// moves are read (limits, pressure advance, temperatures, fans, lights, object labels,
// displays, settings): skipped without a warning. Any other extended command (a user's
// macro: PRINT_START, ...) is skipped with a warning naming it.
bool IsKnownMotionlessCommand(const std::string& name) {
  for (const char* known :
       {"SET_VELOCITY_LIMIT", "SET_PRESSURE_ADVANCE", "SET_FAN_SPEED", "SET_HEATER_TEMPERATURE", "TEMPERATURE_WAIT",
        "SET_TEMPERATURE_FAN_TARGET", "TURN_OFF_HEATERS", "SET_PIN", "SET_LED", "SET_LED_TEMPLATE", "SET_IDLE_TIMEOUT",
        "SET_INPUT_SHAPER", "SET_TMC_CURRENT", "SET_TMC_FIELD", "SET_EXTRUDER_ROTATION_DISTANCE",
        "SYNC_EXTRUDER_MOTION", "BED_MESH_PROFILE", "BED_MESH_CLEAR", "BED_MESH_OUTPUT", "EXCLUDE_OBJECT",
        "EXCLUDE_OBJECT_DEFINE", "EXCLUDE_OBJECT_START", "EXCLUDE_OBJECT_END", "SET_PRINT_STATS_INFO",
        "SET_DISPLAY_TEXT", "SET_DISPLAY_GROUP", "RESPOND", "SAVE_VARIABLE", "SAVE_GCODE_STATE",
        "SET_FILAMENT_SENSOR", "SET_Z_THERMAL_ADJUST", "UPDATE_DELAYED_GCODE", "GET_POSITION", "STATUS",
        "QUERY_ENDSTOPS", "QUERY_PROBE", "CLEAR_PAUSE", "SET_SKEW", "SKEW_PROFILE", "ECHO",
        "SET_GCODE_VARIABLE", "SET_STEPPER_ENABLE", "SET_SERVO", "SET_PAUSE_NEXT_LAYER", "SET_PAUSE_AT_LAYER"}) {
    if (name == known) return true;
  }
  return false;
}

}  // namespace

bool GcodeReader::ExtendedCommand(std::string_view code, size_t pos) {
  // An extended command (Klipper's PRINT_START, EXCLUDE_OBJECT_START NAME=...,
  // SET_PRESSURE_ADVANCE ADVANCE=...): a name of letters, digits and
  // underscores that does not start with a letter and a number. Skipped, counted by name.
  // Klipper's macro names may start with '_' (its "hidden" macros: _PRINT_START). A
  // line starting with '@' is a command to the host (OctoPrint's and Repetier's
  // "@pause", which Cura's Pause at Height script writes), not sent to the printer.
  const bool host_command = code[pos] == '@';
  if (host_command || (pos + 1 < code.size() && (IsLetter(code[pos]) || code[pos] == '_') &&
                       (IsLetter(code[pos + 1]) || code[pos + 1] == '_'))) {
    size_t end = pos;
    while (end < code.size() && !IsBlank(code[end])) ++end;
    std::string name(code.substr(pos, end - pos));
    for (char& ch : name) ch = Upper(ch);
    // Klipper's own commands say the file is for Klipper (its T n are macros then);
    // ECHO is RepRapFirmware's "echo" too.
    if (IsProbingMacro(name) || (IsKnownMotionlessCommand(name) && name != "ECHO") || name == "SET_RETRACTION" ||
        name == "ACTIVATE_EXTRUDER" || name == "SET_GCODE_OFFSET") {
      klipper_ = true;
    }
    if (IsProbingMacro(name)) {
      PositionUnknown(name);
      return true;
    }
    if (name == "SET_RETRACTION") {
      KlipperRetractSettings(code.substr(end));
      return true;
    }
    if (name == "ACTIVATE_EXTRUDER") {
      KlipperActivateExtruder(code.substr(end));
      return true;
    }
    if (name == "SET_GCODE_OFFSET") {
      KlipperGcodeOffset(code.substr(end));
      return true;
    }
    ++path_.skipped_commands[name];
    if (!host_command && !IsKnownMotionlessCommand(name)) UnknownExtendedCommand(name);
    return true;
  }
  return false;
}

}  // namespace gcode_detail
}  // namespace lt

// The G-code reader's commands: which command a line holds and what each does
// (the motion commands are in scene/gcode_moves.cpp, firmware retraction in
// gcode_retraction.cpp, extended commands such as Klipper's in gcode_extended.cpp),
// or how it is skipped and counted.
#include <cmath>
#include <string>
#include <string_view>

#include "scene/gcode_reader.h"
#include "core/text_fields.h"

namespace lt {
namespace gcode_detail {

// G29 forms that load, fill, activate or save a mesh without probing: RepRapFirmware's
// S1 (load the height map), S2 (clear), S3 (save); Marlin's unified bed levelling and
// Prusa's Buddy firmware's A (activate), D (disable), L (load), F (fade), T and W
// (reports), P3 (fill: "G29 P3.2"), P5 and P6, with C and V modifiers, and G (Prusa's
// MK4, XL and Core One start scripts: "G29 G ; absorb heat", a wait). Bare G29, S0,
// P1, J, and any point or area (X, Y, I, J, W with P1; Bambu's "G29 A X.. Y.. I.. J..")
// probe.
bool GcodeReader::MeshCommandOnly() const {
  if (words_.empty()) return false;
  for (const Word& w : words_) {
    const double v = w.value.value_or(0);
    const bool ok = (w.letter == 'S' && w.value && v >= 1 && v <= 3 && v == std::floor(v)) ||
                    (w.letter == 'P' && w.value && (std::floor(v) == 3 || v == 5 || v == 6)) ||
                    (w.letter == 'P' && !w.value) ||  // RepRapFirmware's height map file: S1 P"heightmap.csv"
                    std::string_view("ADLFTWCVG").find(w.letter) != std::string_view::npos;
    if (!ok) return false;
  }
  return true;
}

namespace {

// Whether `text` holds `word` as a blank-separated word (letters in any case).
bool HasWord(std::string_view text, std::string_view word) {
  size_t pos = 0;
  while (pos < text.size()) {
    while (pos < text.size() && IsBlank(text[pos])) ++pos;
    size_t end = pos;
    while (end < text.size() && !IsBlank(text[end])) ++end;
    if (end - pos == word.size()) {
      bool same = true;
      for (size_t i = 0; i < word.size(); ++i) same = same && Upper(text[pos + i]) == Upper(word[i]);
      if (same) return true;
    }
    pos = end;
  }
  return false;
}

// The value of the first word `letter` (either case) in a skipped command's text
// ("M135 T1": 1); none if absent or not a number.
std::optional<double> SkippedWordValue(std::string_view params, char letter) {
  for (std::string_view word : SplitBlanks(params)) {
    if (word.size() >= 2 && Upper(word[0]) == letter) return ParseFiniteNumber(word.substr(1));
  }
  return std::nullopt;
}

}  // namespace

// Axis words without a command on their line: the last G0-G3 again, as RS-274 makes the
// motion mode modal (LinuxCNC, Grbl, RepRapFirmware; Marlin with GCODE_MOTION_MODES).
// Legacy Cura's start scripts hold such lines ("G0 X100 Y100" then "Z10"), which were
// an error that stopped the read. Marlin without that option ignores the line, so what
// the printer does depends on its firmware: warned, with the line and the count.
void GcodeReader::ModalMotion(std::string_view code, size_t pos) {
  std::string text(1, '"');  // appended: GCC 12 warns falsely on "\"" + std::string
  text.append(TrimBlanks(code.substr(pos)));
  text += "\": axis words without a command, read as " + CommandName('G', motion_mode_) +
          ", the last motion command (RS-274's modal motion, as Grbl and RepRapFirmware read it; Marlin without "
          "GCODE_MOTION_MODES ignores such a line)";
  Warn(kModalMotion, text);
  ++commands_on_line_;
  ReadWords(code, pos, true);
  if (motion_mode_ <= 1) {
    Move(motion_mode_);
  } else {
    Arc(motion_mode_);
  }
}

void GcodeReader::ReadCommand(std::string_view code, size_t pos) {
  if (ExtendedCommand(code, pos)) return;
  char letter = Upper(code[pos]);
  // P: Prusa firmware's (Buddy: XL) "P0 S1 L2 D0", parking the tool in its dock.
  const bool park = letter == 'P' && pos + 1 < code.size() && code[pos + 1] >= '0' && code[pos + 1] <= '9';
  if (letter == 'F') {
    // A line holding only F sets the feed, RS-274's form (CNC post-processors, Mach3's
    // "F140 ;(Initialize feed rate)"): no motion, whatever the motion mode. It was read
    // as the last G0-G3 again (after a G2: "G2 needs I/J"), or refused before any.
    ReadWords(code, pos, true);
    if (words_.size() == 1) {
      ++commands_on_line_;
      SetFeed();
      return;
    }
  }
  if (std::string_view("XYZEFIJKR").find(letter) != std::string_view::npos && motion_mode_ >= 0) {
    ModalMotion(code, pos);
    return;
  }
  if (letter != 'G' && letter != 'M' && letter != 'T' && !park) {
    Fail("expected a command (G, M or T), got \"" + std::string(code.substr(pos)) + "\"");
  }
  size_t start = ++pos;
  while (pos < code.size() && IsNumberChar(code[pos])) ++pos;
  std::string_view number = code.substr(start, pos - start);
  if (number.empty() && letter == 'T' && pos < code.size() && !IsBlank(code[pos])) {
    // Prusa firmware's MMU tool commands "Tx", "Tc", "T?": skipped, counted by name.
    std::string name = "T";
    for (; pos < code.size() && !IsBlank(code[pos]); ++pos) name += Upper(code[pos]);
    ++path_.skipped_commands[name];
    return;
  }
  if (number.empty()) Fail(std::string(1, letter) + " without a number");
  auto value = ParseFiniteNumber(number);
  if (!value) Fail(std::string(1, letter) + " has a malformed number \"" + std::string(number) + "\"");
  const bool integral = *value == std::floor(*value) && std::abs(*value) < 1e6;
  const int n = integral ? int(*value) : -1;
  ++commands_on_line_;
  // G38.2-G38.5: a straight probe towards the point, stopping where the probe triggers.
  if (letter == 'G' && (number == "38.2" || number == "38.3" || number == "38.4" || number == "38.5")) {
    ReadWords(code, pos, false);
    std::string name(1, 'G');  // appended: GCC 12 warns falsely on "G" + std::string
    name.append(number);
    PositionUnknown(name);
    return;
  }
  // Bambu's z-trim "G29.1 Z-0.02" (its start scripts lower the nozzle so on a textured
  // plate, and clear it with Z0): an offset of later moves, as Klipper's Z offset.
  // Another G29.1 (other words: no firmware of those read here) is skipped.
  if (letter == 'G' && number == "29.1") {
    ReadWords(code, pos, false);
    if (words_.size() == 1 && words_[0].letter == 'Z' && words_[0].value) {
      ZTrim(*words_[0].value * unit_mm_);
    } else {
      ++path_.skipped_commands["G29.1"];
    }
    return;
  }
  // G92.1-G92.3 (G92's offset cleared, cleared and saved, restored); G59.1-G59.3 (the
  // seventh to ninth work coordinate systems).
  if (letter == 'G' && number.size() == 4 && (StartsWith(number, "92.") || StartsWith(number, "59.")) &&
      number[3] >= '1' && number[3] <= '3') {
    ReadWords(code, pos, true);
    if (number[0] == '9') {
      ResetPosition(number[3] - '0');
    } else {
      std::string name(1, 'G');  // appended: GCC 12 warns falsely on "G" + std::string
      name.append(number);
      Expect("", name);
      SelectWorkSystem(6 + number[3] - '1');
    }
    return;
  }
  if (letter == 'G' && integral) {
    switch (n) {
      case 0:
      case 1: motion_mode_ = n; ReadWords(code, pos, true); Move(n); return;
      case 2:
      case 3: motion_mode_ = n; ReadWords(code, pos, true); Arc(n); return;
      case 4: ReadWords(code, pos, true); Dwell(); return;
      case 5:
        // Alone, it moves nothing: Anycubic's firmware enables its resume after a power
        // loss so (Cura's start script for the i3 Mega ends with a bare "G5"). Skipped.
        ReadWords(code, pos, false);
        if (words_.empty()) {
          ++path_.skipped_commands["G5"];
          return;
        }
        Bezier();
        return;
      case 10:
        ReadWords(code, pos, true);
        if (words_.empty()) {
          FirmwareRetract(true);
          return;
        }
        if (const Word* l = Find('L'); l && (*l->value == 2 || *l->value == 20)) {
          SetWorkOffset(int(*l->value));  // a work coordinate system's offset
          return;
        }
        // Marlin's swap retraction (multi-extruder: before a tool swap, by M207 W).
        if (words_.size() == 1 && words_[0].letter == 'S' && *words_[0].value == 1) {
          FirmwareRetract(true, true);
          return;
        }
        // With other parameters: tool offsets and temperatures (RepRapFirmware's G10 P,
        // G10 L1; "G10 S0" without P sets the active tool's temperature there): skipped.
        ++path_.skipped_commands["G10"];
        return;
      case 11: ReadWords(code, pos, true); Expect("", "G11"); FirmwareRetract(false); return;
      case 17:
      case 18:
      case 19: ReadWords(code, pos, true); Expect("", CommandName('G', n)); plane_ = n; return;
      case 20:
      case 21: ReadWords(code, pos, true); Expect("", CommandName('G', n)); unit_mm_ = n == 20 ? 25.4 : 1.0; return;
      case 28:
        // T is a parameter here: Bambu's "G28 Z P0 T300" (home Z with low precision,
        // permitting a nozzle of up to 300 degrees), not a tool change.
        ReadWords(code, pos, false, true);
        Home();
        return;
      case 29:  // bed levelling (Marlin, RepRapFirmware, Bambu): probes the bed
      case 30:  // a single Z probe
      case 32:  // RepRapFirmware's bed.g (probing); Marlin's sled undock
      case 33:  // delta auto-calibration
      case 34:  // Z steppers' auto-alignment (probes)
      case 35:  // Marlin's tramming assistant (probes the screws' points)
      case 380:  // Bambu's move until contact ("G380 S2 Z-5 F300")
        // T is G29's parameter (Marlin's and Prusa's "G29 T": report the mesh), no tool.
        ReadWords(code, pos, false, n == 29);
        if (n == 29 && MeshCommandOnly()) {
          ++path_.skipped_commands["G29"];
          return;
        }
        PositionUnknown(CommandName('G', n));
        return;
      case 161:  // MakerBot, Sailfish: home to the minimum endstops ("G161 X Y F2500")
      case 162:  // ... to the maximum ("G162 Z F500"), usually followed by G92 or M132
        ReadWords(code, pos, false);
        Expect("XYZF", CommandName('G', n));
        HomeToEndstops(CommandName('G', n), true);
        return;
      case 12:  // Marlin's nozzle clean (a pattern at a configured place; going back is an option)
      case 27:  // Marlin's nozzle park (at the configured park point)
      case 280:  // Ultimaker's Griffin firmware: prime blob at the printer's prime position
        ReadWords(code, pos, false);
        ++path_.skipped_commands[CommandName('G', n)];
        PositionUnknown(CommandName('G', n), false);
        return;
      case 80:
        // Prusa firmware's mesh bed levelling, alone on its line; RS-274's "cancel canned
        // cycle" in a CNC header ("G17 G80 G90") moves nothing.
        ReadWords(code, pos, false);
        if (commands_on_line_ == 1 && next_command_.empty()) {
          PositionUnknown("G80");
        } else {
          ++path_.skipped_commands["G80"];
          motion_mode_ = -1;  // RS-274's G80 cancels the motion mode: axis words alone are an error again
        }
        return;
      case 53:  // machine coordinates for the rest of the line ("G53 G1 X0 Y200")
        ReadWords(code, pos, true);
        Expect("", "G53");
        machine_coordinates_ = true;
        return;
      case 54:
      case 55:
      case 56:
      case 57:
      case 58:
      case 59: ReadWords(code, pos, true); Expect("", CommandName('G', n)); SelectWorkSystem(n - 54); return;
      case 90:
      case 91: ReadWords(code, pos, true); Expect("", CommandName('G', n)); xyz_relative_ = n == 91; return;
      case 92: ReadWords(code, pos, true); SetPosition(); return;
      default: break;
    }
  }
  if (letter == 'M' && (n == 2 || n == 30)) {
    // Program end (RS-274, RepRapFirmware, Klipper's M2-less world aside): nothing
    // after it runs. Marlin's "M30 name" deletes a file on the SD card: skipped.
    if (n == 30 && !TrimBlanks(code.substr(pos)).empty()) {
      ++path_.skipped_commands["M30"];
      return;
    }
    path_.program_end_line = line_no_;
    path_.program_end_command = CommandName('M', n);
    return;
  }
  if (letter == 'M' && n == 132) {  // MakerBot, Sailfish: "M132 X Y Z A B", the stored home offsets
    ReadWords(code, pos, false);
    Expect("XYZAB", "M132");
    HomeToEndstops("M132", false);
    return;
  }
  if (letter == 'M' && n == 48) {  // Marlin's probe repeatability test: probes around a point
    ReadWords(code, pos, false);
    PositionUnknown("M48");
    return;
  }
  if (letter == 'M' && n == 290) {
    ReadWords(code, pos, true);
    Babystep();
    return;
  }
  if (letter == 'M' && n == 200) {
    ReadWords(code, pos, true, true);
    VolumetricExtrusion();
    return;
  }
  if (letter == 'M' && n == 208) {
    // Marlin's recovery settings (S, F; W, R the swap's); RepRapFirmware's axis limits
    // name axes or give ranges ("M208 X0:200 Y0:200", "M208 S1 Z-0.2") and are skipped.
    if (code.substr(pos).find_first_of("XYZUVABCxyzuvabc:") != std::string_view::npos) {
      ++path_.skipped_commands["M208"];
      return;
    }
    ReadWords(code, pos, true);
    RecoverSettings();
    return;
  }
  if (letter == 'M' && (n == 220 || n == 221)) {
    ReadWords(code, pos, false, true);
    // Bambu's start scripts switch soft endstops with "M221 X0 Y0 Z0", and push and
    // pop their state with a bare "M221 S" and "M221 R" (X1 and P1 start scripts, around
    // the nozzle wipe below the bed's surface): skipped.
    const Word* s = Find('S');
    if (n == 221 && (Find('X') || Find('Y') || Find('Z') || Find('R') || (s && !s->value))) {
      ++path_.skipped_commands["M221"];
      return;
    }
    n == 220 ? SpeedFactor() : FlowFactor();
    return;
  }
  if (letter == 'M' && n == 207) {
    ReadWords(code, pos, true, true);
    RetractSettings();
    return;
  }
  if (letter == 'M' && (n == 82 || n == 83)) {
    ReadWords(code, pos, true);
    Expect("", CommandName('M', n));
    e_mode_ = n == 82 ? EMode::kAbsolute : EMode::kRelative;
    return;
  }
  std::string name(1, letter);
  name += integral ? std::to_string(n) : std::string(number);
  ++path_.skipped_commands[name];
  if (letter == 'M' && (n == 101 || n == 103)) {  // extruder on, off: see ExtruderOnWithoutE
    extruder_on_ = n == 101;
    if (n == 101) m101_line_ = line_no_;
  }
  if (letter == 'M' && n == 98 && integral) MacroFileCall(code.substr(pos));
  if (letter == 'M' && (n == 3 || n == 4) && integral && spindle_on_since_.empty()) {
    spindle_on_since_ = name + " (line " + std::to_string(line_no_) + ")";  // see MoveS
  }
  // Bambu Lab's pause is "M400 U1" (its printers' machine_pause_gcode); M400 alone waits for the moves.
  if (letter == 'M' && integral && (n != 400 || HasWord(code.substr(pos), "U1"))) PauseForUser(n, code.substr(pos));
  if (letter == 'T') {
    if (klipper_) {
      KlipperToolMacro(n);
    } else {
      SelectTool(n);
    }
  }
  // MakerBot's tool changes by M code (GPX and ReplicatorG: "M135 T1", "M6 T1" and
  // ReplicatorG's "M108 T1"), LinuxCNC's "M6 T1" too: the named tool becomes the active
  // one, whose axis E is in a file that prints with A and B. Without T they change nothing
  // here (Marlin's M108 ends a heating wait, RepRapFirmware's M135 sets a PID interval).
  if (letter == 'M' && (n == 6 || n == 108 || n == 135)) {
    const std::optional<double> tool = SkippedWordValue(code.substr(pos), 'T');
    if (tool && *tool >= 0 && *tool < 1e6 && *tool == std::floor(*tool)) SelectTool(int(*tool));
  } else if (letter == 'M' && integral && extruder_axes_ == ExtruderAxes::kEIsActiveAB) {
    ToolWordOnMCommand(name, SkippedWordValue(code.substr(pos), 'T'));  // (its words read only where they matter)
  }
  // Marlin's M605 (DUAL_X_CARRIAGE: S0 full control, S1 auto-park, S2 duplication, S3
  // mirrored; BCN3D's Sigma firmware mirrors with S4): from S2 on the second carriage
  // prints a copy of every move, which the toolpath (one nozzle) does not hold.
  if (letter == 'M' && n == 605) {
    const std::optional<double> mode = SkippedWordValue(code.substr(pos), 'S');
    if (mode && *mode >= 2) {
      WarnOncePerName("M605 duplication", "M605 S" + FormatNumber(*mode) +
                                               ": the second carriage of a dual-carriage (IDEX) printer duplicates "
                                               "(S2) or mirrors (S3, BCN3D's S4) the print; that copy is not in the "
                                               "toolpath, which follows one nozzle");
    }
  }
  // The nozzle moves to the dock and, for a park or a tool change with D0 (Prusa's
  // XL: "T1 S1 L0 D0", do not return), stays there: where is the firmware's.
  if (park || (letter == 'T' && HasWord(code.substr(pos), "D0"))) PositionUnknown(name, false);
}

}  // namespace gcode_detail
}  // namespace lt

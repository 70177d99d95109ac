// The G-code reader's axes beyond the modelled X, Y, Z and extruders: a position
// that probing left unknown, and extra axes (U, V, W, C) that are ignored; how a file
// uses E, A and B (ExtruderAxes); and the warnings that say so (Toolpath::warnings).
#include <string>

#include "core/error.h"
#include "scene/gcode_reader.h"
#include "core/text_fields.h"

namespace lt {
namespace gcode_detail {

namespace {

// A and B last: they are extra axes only in a file that prints with E (ExtruderAxes::kABExtra).
constexpr char kExtraAxisLetters[6] = {'U', 'V', 'W', 'C', 'A', 'B'};

}  // namespace

std::string ExtraAxesWarning(const std::string& axes) {
  std::string list;
  for (size_t i = 0; i < axes.size(); ++i) list += (i ? ", " : "") + std::string(1, axes[i]);
  return "axis " + list +
         " ignored: the toolpath models X, Y, Z and the extruders (U, V, W and C drive a tool changer's coupler, a "
         "second carriage or a rotary axis" +
         std::string(axes.find_first_of("AB") != std::string::npos
                         ? "; A and B are no extruders here, since the file's print moves extrude with E"
                         : "") +
         "); none of them moves while the file extrudes";
}

void GcodeReader::Warn(WarningKind kind, const std::string& text) {
  int& index = warning_index_[kind];
  if (index < 0) {
    index = int(path_.warnings.size());
    path_.warnings.push_back(ToolpathWarning{line_no_, 0, text});
  }
  ++path_.warnings[size_t(index)].count;
}

void GcodeReader::PositionUnknown(const std::string& command, bool probing) {
  for (bool& known : axis_known_) known = false;
  unknown_since_ = command + " (line " + std::to_string(line_no_) + ")";
  // How long probing takes depends on the printer's configuration (points, speeds,
  // samples), not on the file: no duration is sound, so it takes none, with a warning.
  if (probing) {
    Warn(kProbingTime, command +
                           " (probing, levelling) takes no time in the toolpath: a printer spends seconds to minutes "
                           "there, so every time after it (the printed part's, a scan's) is early by as much");
  }
}

void GcodeReader::WarnOncePerName(const std::string& name, const std::string& text) {
  auto [it, first] = unknown_command_warning_.emplace(name, path_.warnings.size());
  if (first) path_.warnings.push_back(ToolpathWarning{line_no_, 0, text});
  ++path_.warnings[it->second].count;
}

void GcodeReader::PauseForUser(int n, std::string_view params) {
  if (n == 0 || n == 1) {
    // Marlin's M0/M1 [P<ms>] [S<s>] [message]: with a time, the stop ends by itself.
    double seconds = 0;
    bool timed = false;
    for (std::string_view word : SplitBlanks(params)) {
      const char letter = Upper(word[0]);
      if (letter != 'P' && letter != 'S') continue;
      const std::optional<double> v = ParseFiniteNumber(word.substr(1));
      if (!v || *v < 0) continue;  // a message's word ("Press", "S-")
      seconds += letter == 'P' ? *v / 1000.0 : *v;
      timed = true;
    }
    if (timed) {
      const std::string name = CommandName('M', n) + " with a time";
      WarnOncePerName(name, CommandName('M', n) +
                                " with a time (Marlin: a stop that ends when the user resumes or the time passes), "
                                "taken as a dwell of its whole time");
      if (seconds > 0) AddDwell(seconds);
      return;
    }
  }
  const char* what = n == 0 || n == 1 ? "a stop until the user resumes (Marlin; Cura's Pause at Height)"
                     : n == 25        ? "a pause of the print (Marlin's and RepRapFirmware's SD print)"
                     : n == 226       ? "a pause the file asks for (RepRapFirmware, Marlin)"
                     : n == 600       ? "a filament change (the nozzle parks, the printer waits for the new filament "
                                        "and returns; the park and return moves are not in the toolpath either)"
                     : n == 601       ? "a pause (Prusa firmware)"
                     : n == 400       ? "Bambu Lab's pause (its printers' pause G-code)"
                                      : nullptr;
  if (!what) return;
  const std::string name = n == 400 ? "M400 U1" : CommandName('M', n);
  WarnOncePerName(name, name + ", " + what +
                            ", takes no time in the toolpath: every time after it (the printed part's, a scan's) is "
                            "early by as long as the printer waits");
}

void GcodeReader::UnknownExtendedCommand(const std::string& name) {
  WarnOncePerName(name, name +
                            " skipped: a command the reader does not know (a macro of the printer's configuration?); "
                            "whatever it does (homing, probing, heating, purge moves) is not in the toolpath or its "
                            "times");
}

void GcodeReader::MacroFileCall(std::string_view params) {
  const size_t open = params.find("P\"") != std::string_view::npos ? params.find("P\"") : params.find("p\"");
  if (open == std::string_view::npos) return;
  const size_t close = params.find('"', open + 2);
  const std::string call = "M98 P\"" + std::string(params.substr(open + 2, close == std::string_view::npos ? std::string_view::npos : close - open - 2)) + "\"";
  WarnOncePerName(call, call +
                            " skipped: a macro file of the printer's (RepRapFirmware) the reader does not have; "
                            "whatever it does (homing, probing, heating, purge moves) is not in the toolpath or its "
                            "times");
}

void GcodeReader::ExtruderOnWithoutE() {
  Warn(kExtruderOnWithoutE,
       "moves without E while M101 (line " + std::to_string(m101_line_) +
           ") has the extruder on: the 3D-era RepRap and MakerBot form (Skeinforge for the Thing-O-Matic), where "
           "the firmware feeds at M108's speed until M103; how much such moves extrude is not in the file, so they "
           "lay no bead in the toolpath");
}

void GcodeReader::TrackKnownAxes(const std::string& command, int arc_axes) {
  const char axes[3] = {'X', 'Y', 'Z'};
  std::string unknown;
  for (int k = 0; k < 3; ++k) {
    // An arc's centre is an offset from its start (or, with R, found from it): an
    // unknown start in its plane puts it off too.
    const bool named = Find(axes[k]) != nullptr;
    if (!axis_known_[k] && ((named && xyz_relative_) || (arc_axes & (1 << k)))) {
      unknown += axes[k];
    }
  }
  if (!unknown.empty()) {
    const Eigen::Vector3d last = pos_mm_ - offset_mm_;
    Warn(kRelativeFromUnknown,
         command + " moves relative to a position " + unknown_since_ + " left unknown in " + unknown +
             " (probing and docking end where the firmware stops): built from the last known position X" +
             FormatNumber(last.x() / unit_mm_) + " Y" + FormatNumber(last.y() / unit_mm_) + " Z" +
             FormatNumber(last.z() / unit_mm_) + "; the path after it is off by as much until an absolute move on each axis");
  }
  for (int k = 0; k < 3; ++k) {
    if (Find(axes[k]) && !xyz_relative_) axis_known_[k] = true;
  }
}

void GcodeReader::WarnBeadAtUnknown(const std::string& command, double extruded_mm, double xy_length_mm) {
  if (!(extruded_mm > 0) || !(xy_length_mm > 0)) return;
  const char axes[3] = {'X', 'Y', 'Z'};
  const Eigen::Vector3d last = pos_mm_ - offset_mm_;
  std::string unknown;
  for (int k = 0; k < 3; ++k) {
    if (!axis_known_[k]) unknown += std::string(unknown.empty() ? "" : " ") + axes[k] + FormatNumber(last[k] / unit_mm_);
  }
  if (unknown.empty()) return;
  Warn(kBeadAtUnknown, command + " extrudes while " + unknown_since_ +
                           " left the position unknown (probing and docking end where the firmware stops): its bead "
                           "is laid at the last known " + unknown +
                           "; the beads are off by as much until an absolute move on each axis");
}

void GcodeReader::KlipperGcodeOffset(std::string_view params) {
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();
  bool move = false;
  double move_speed = 0;
  const char* axes[3] = {"X", "Y", "Z"};
  for (const auto& [key, text] : KeyValues(params)) {
    auto v = ParseFiniteNumber(text);
    if (!v) Fail("SET_GCODE_OFFSET " + key + " must be a number, got \"" + std::string(text) + "\"");
    for (int k = 0; k < 3; ++k) {
      // Klipper's offsets are millimetres whatever G20 says.
      if (key == axes[k]) delta[k] = *v - klipper_offset_mm_[k];
      if (key == std::string(axes[k]) + "_ADJUST") delta[k] = *v;
    }
    if (key == "MOVE") move = *v != 0;
    if (key == "MOVE_SPEED") {
      if (!(*v > 0)) Fail("SET_GCODE_OFFSET MOVE_SPEED must be > 0, got \"" + std::string(text) + "\"");
      move_speed = *v;
    }
  }
  for (int k = 0; k < 3; ++k) klipper_offset_mm_[k] += delta[k];
  offset_mm_ += delta;  // later absolute moves; relative ones go on from where the nozzle is
  if (move) {
    const Eigen::Vector3d end = pos_mm_ + delta;
    AddSegment(1, end, 0, delta.norm(), delta.head<2>().norm(), nullptr,
               move_speed > 0 ? move_speed : MoveFeed(delta.norm(), 0));
  }
}

ExtruderAxes GcodeReader::CalledFor() const {
  if (!ab_named_) return ExtruderAxes::kSeparate;
  // A file that prints with E and names A and B each only under its own tool (QIDI
  // Print's start script primes both nozzles: "T1", "G1 X330 B19", "T0", "G1 X5 A19")
  // uses them as the tools' extruder axes: each keeps its own position beside E.
  if (xy_moves_e_ > xy_moves_ab_) {
    return b_on_move_ && !ab_off_their_tool_ ? ExtruderAxes::kSeparate : ExtruderAxes::kABExtra;
  }
  return e_on_move_ ? ExtruderAxes::kEIsActiveAB : ExtruderAxes::kSeparate;
}

ExtruderAxes GcodeReader::RereadAs() const {
  return extruder_axes_ == ExtruderAxes::kSeparate ? CalledFor() : ExtruderAxes::kSeparate;
}

void GcodeReader::NoteExtruderAxes() {
  const bool ab = Find('A') || Find('B');
  ab_named_ = ab_named_ || ab;
  b_on_move_ = b_on_move_ || Find('B');
  ab_off_their_tool_ = ab_off_their_tool_ || (Find('A') && active_tool_ != 0) || (Find('B') && active_tool_ != 1);
  e_on_move_ = e_on_move_ || Find('E');
  if (!Find('X') && !Find('Y')) return;
  if (Find('E')) ++xy_moves_e_;
  if (ab) ++xy_moves_ab_;
}

bool GcodeReader::ExtraAxes(const std::string& command, double extruded_mm, ExtraAxesUse use) {
  bool named = false;
  for (int k = 0; k < (ABAreExtruders() ? 4 : 6); ++k) {
    const Word* w = Find(kExtraAxisLetters[k]);
    // Prusa firmware's "G28 W" homes X, Y and Z without mesh levelling: W is no axis there.
    if (!w || (use == ExtraAxesUse::kHome && kExtraAxisLetters[k] == 'W')) continue;
    double target = 0;  // homed
    if (use == ExtraAxesUse::kSet) target = *w->value;
    if (use == ExtraAxesUse::kMove) target = xyz_relative_ ? extra_axes_[k] + *w->value : *w->value;
    if (extruded_mm > 0 && target != extra_axes_[k]) {
      Fail(command + " moves the " + std::string(1, kExtraAxisLetters[k]) +
           " axis while it extrudes: an extra axis (a second carriage, a rotary axis) moving during a print move "
           "changes the printed path, which a toolpath of X, Y and Z cannot hold");
    }
    extra_axes_[k] = target;
    if (extra_axes_seen_.find(kExtraAxisLetters[k]) == std::string::npos) extra_axes_seen_ += kExtraAxisLetters[k];
    named = true;
  }
  if (named) Warn(kExtraAxes, ExtraAxesWarning(extra_axes_seen_));
  return named;
}

}  // namespace gcode_detail
}  // namespace lt

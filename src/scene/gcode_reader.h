// Internal to the G-code reader (scene/gcode.cpp and the scene/gcode_*.cpp files
// that hold its parts), not an API: use ParseGcode and ReadGcode (scene/gcode.h).
// The reader's state machine, the parameter words of a line, and the constants and
// helpers that more than one of its files needs.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"
#include "scene/toolpath.h"

namespace lt {
namespace gcode_detail {

constexpr double kMetresPerMm = 1e-3;
// Curves the toolpath does not hold as arcs (G18/G19 arcs, G5 Bezier moves) become
// straight chords off the curve by at most this (mm), and at most this many per move.
constexpr double kChordSagittaMm = 1e-3;
constexpr double kMaxChords = 100000;

// "G1", "M83" (built by appending: GCC 12 warns falsely on "G" + std::string).
inline std::string CommandName(char letter, int n) {
  std::string name(1, letter);
  name.append(std::to_string(n));
  return name;
}

inline bool IsLetter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
inline char Upper(char c) { return (c >= 'a' && c <= 'z') ? char(c - 'a' + 'A') : c; }
inline bool IsNumberChar(char c) { return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+'; }
inline bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
// The KEY=value words of an extended command (Klipper's), keys in upper case; words
// without '=' are left out.
std::vector<std::pair<std::string, std::string_view>> KeyValues(std::string_view params);

// The warning for extra axes (U, V, W, C) ignored, naming them ("UC").
std::string ExtraAxesWarning(const std::string& axes);

inline bool StartsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// How the extruder words E, A and B are read (ParseGcode decides from a first read):
// kSeparate: each is an extruder axis with its own position (Cura's and PrusaSlicer's
// Mach3 and Machinekit flavours extrude on A, MakerBot's second extruder on B).
// kABExtra: A and B are extra axes (a rotary axis, a ring), ignored as U, V, W and C
// are, in a file that prints with E. kEIsActiveAB: E is the active tool's axis (A for
// T0, B for T1), one position with it, as MakerBot's and Sailfish's G-code (GPX) read
// it, in a file that prints with A or B.
enum class ExtruderAxes { kSeparate, kABExtra, kEIsActiveAB };

// One parameter word: a letter and (for most commands, required) a number.
struct Word {
  char letter = 0;
  std::optional<double> value;
};

class GcodeReader {
 public:
  explicit GcodeReader(const std::string& name, ExtruderAxes axes = ExtruderAxes::kSeparate) : name_(name) {
    extruder_axes_ = axes;
    for (Eigen::Vector3d& offset : work_offset_mm_) offset.setZero();
  }

  // The file is for Klipper (its flavour comment, found anywhere in the file: a
  // PrusaSlicer config block comes at the end): see klipper_.
  void SetKlipper() { klipper_ = true; }
  // Room for n segments (a hint: more are appended as needed).
  void ReserveSegments(size_t n) { path_.segments.reserve(n); }
  void ReadLine(std::string_view line, int line_no);
  // After M2/M30: the program has ended, later lines are not executed.
  bool Ended() const { return path_.program_end_line > 0; }
  Toolpath Finish();
  // How a file read with ExtruderAxes::kSeparate should be read again, from the moves
  // (G0-G3) that name A or B and those with X or Y that give E or A/B: kABExtra where E
  // prints and A or B also appear (more of those moves give E than A or B), unless they
  // keep MakerBot's convention (B named, every A under T0 and every B under T1: QIDI's
  // primes of both nozzles), which is kSeparate; kEIsActiveAB
  // where A or B print and E also appears on a move (MakerBot's start script primes
  // with E); kSeparate (no second read) otherwise.
  ExtruderAxes RereadAs() const;
  // The reading the moves read so far call for, whatever this reader's: as RereadAs
  // for a kSeparate reader (ParseGcode's second try after a first read that failed).
  ExtruderAxes CalledFor() const;

 private:
  // The largest coordinate a move may reach (mm): no machine's axes span 1 km.
  static constexpr double kMaxCoordinateMm = 1e6;
  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(name_ + ":" + std::to_string(line_no_), message);
  }

  // An approximation of the file (Toolpath::warnings): the first of each kind keeps
  // its line and text, later ones are counted.
  enum WarningKind {
    kUnclosedParen,
    kRelativeFromUnknown,
    kExtraAxes,
    kProbingTime,
    kBeadAtUnknown,
    kModalMotion,
    kExtruderOnWithoutE,
    kEAsActiveAB,
    kWarningKinds
  };
  void Warn(WarningKind kind, const std::string& text);
  int warning_index_[kWarningKinds] = {-1, -1, -1, -1, -1, -1, -1, -1};
  // At the end (the layers known): filament laid in place inside a layer (a blob, in no
  // bead) is warned, at its first line, with the count and the amount.
  void WarnBlobsInLayers();
  // A line of axis words without a command ("Z10" in a legacy Cura start script): the
  // last motion command again (RS-274's modal motion), warned.
  void ModalMotion(std::string_view code, size_t pos);
  int motion_mode_ = -1;  // the last G0-G3 read (-1: none yet)
  // An extended command (a name: Klipper's commands, a printer's macros) or a command
  // to the host ("@pause") at code[pos]: read or skipped (scene/gcode_extended.cpp).
  // Returns false when code[pos] starts no such command.
  bool ExtendedCommand(std::string_view code, size_t pos);
  // An extended command the reader does not know (a macro of the printer's
  // configuration: PRINT_START, ...): skipped, one warning per distinct name.
  void UnknownExtendedCommand(const std::string& name);
  // RepRapFirmware's M98 P"file.g": runs a macro file of the printer's (homing, probing,
  // a purge): skipped, one warning per file.
  void MacroFileCall(std::string_view params);
  // T n (and MakerBot's M135 T n, M6 T n, M108 T n): tool n is the active one; n < 0
  // (RepRapFirmware's T-1) changes nothing.
  void SelectTool(int n);
  // Klipper's ACTIVATE_EXTRUDER EXTRUDER=extruderN: tool N, E restarting at 0, flow 100 %.
  void KlipperActivateExtruder(std::string_view params);
  void ActivateKlipperExtruder(int tool);
  // "T n" in a Klipper file: a macro of the printer's configuration (Klipper has no T
  // command), read as the ACTIVATE_EXTRUDER it calls, warned.
  void KlipperToolMacro(int n);
  // A T word on another M command in the MakerBot reading (kEIsActiveAB: "M104 S220
  // T1"): the tool the command is for, the active tool unchanged, as GPX reads it;
  // warned, since ReplicatorG makes it the active tool.
  void ToolWordOnMCommand(const std::string& command, std::optional<double> tool);
  // M0, M1, M25, M226, M600, M601, M400 (called with U1 only: Bambu's pause) (a stop,
  // pause or filament change that waits for the user: Cura's Pause at Height,
  // PrusaSlicer's colour change): skipped, one warning per command, since every time
  // after it is early by the wait. Other n: nothing. M0/M1 with a time (Marlin's
  // "M0 S5", "M1 P500": a stop that ends when the user resumes or the time passes) is
  // a dwell of that time instead, warned as such (`params`: the words after the command).
  void PauseForUser(int n, std::string_view params);
  // One warning per distinct name (`text` the first time), counting each occurrence.
  void WarnOncePerName(const std::string& name, const std::string& text);
  std::map<std::string, size_t> unknown_command_warning_;  // name -> index in path_.warnings

  void Comment(std::string_view comment);
  std::optional<double> CommentNumber(std::string_view text, const char* what) const;
  // The command at code[pos] (after any line number) and its words.
  void ReadCommand(std::string_view code, size_t pos);
  // Splits the words after the command. `numbers_required`: every letter needs a number;
  // `t_parameter`: T is a parameter (M207's), not a tool change. A G or M word
  // ends them: it starts the line's next command (`next_command_`; "G21 G90").
  void ReadWords(std::string_view code, size_t pos, bool numbers_required, bool t_parameter = false);
  std::string_view next_command_;
  const Word* Find(char letter) const;
  void Expect(std::string_view allowed, const std::string& command) const;

  void Move(int gcode);
  void Arc(int gcode);
  // G5 (Marlin's cubic Bezier move, BEZIER_CURVE_SUPPORT): scene/gcode_bezier.cpp.
  void Bezier();
  void Dwell();
  void AddDwell(double seconds);  // a segment standing still for `seconds` (> 0)
  void Home();
  // G92 (set the position: an offset of later absolute moves), G92.1 and G92.2 (G92's
  // offset cleared; .2 keeps it for G92.3, which restores it): scene/gcode_offsets.cpp.
  void SetPosition();
  void ResetPosition(int variant);
  // G54-G59, G59.1-G59.3: the work coordinate system (0-8) whose offset later absolute
  // moves take; G10 L2 (an offset) and L20 (the current position's coordinate) set one.
  void SelectWorkSystem(int index);
  void SetWorkOffset(int l);
  // M290: babystepping (Marlin, RepRapFirmware): the nozzle moves now and later moves
  // land that much further, until the axis is homed.
  void Babystep();
  // Bambu's G29.1 Z: the z-trim (mm, not cumulative), an offset of later moves.
  void ZTrim(double z_mm);
  double z_trim_mm_ = 0;
  // Homing axis k (0-2) clears G92's offset and babystepping on it; work offsets and
  // Klipper's SET_GCODE_OFFSET stay.
  void HomeAxis(int k);
  // MakerBot's and Sailfish's G161/G162 (home the named axes, or all, to the minimum or
  // maximum endstops; `homing`) and M132 (recall the home offsets stored in the printer):
  // the axes end where the printer's configuration says, unknown to the file, and G92's
  // offset on them is gone. A G92 on an unknown axis states its place (SetPosition).
  void HomeToEndstops(const std::string& command, bool homing);
  // The offsets that are physical shifts (Klipper's SET_GCODE_OFFSET, Bambu's z-trim,
  // babystepping, a firmware retraction's Z hop), which G53's machine coordinates keep; and with the
  // active work system's offset: all but G92's.
  Eigen::Vector3d PhysicalOffset() const;
  Eigen::Vector3d OffsetWithoutG92() const { return PhysicalOffset() + work_offset_mm_[work_system_]; }
  void SetFeed();
  // Probing and levelling (G29, G30, G32-G34, G38.2-5, Prusa's G80, M48, Klipper's
  // BED_MESH_CALIBRATE, ...) end where the firmware stops: X, Y and Z unknown.
  // `probing`: the command probes (warned: it takes no time here); false for a tool
  // parked in its dock.
  void PositionUnknown(const std::string& command, bool probing = true);
  // Whether a G29's words only load, fill, activate or save a mesh (no probing).
  bool MeshCommandOnly() const;
  // Before a move: its absolute X/Y/Z words make those axes known again; a relative
  // one on an unknown axis (or an arc, whose centre is relative, from a start unknown
  // in its plane) is built from the last known position, with a warning.
  // `arc_axes`: a mask (1 << axis) of the axes of an arc's plane.
  void TrackKnownAxes(const std::string& command, int arc_axes);
  // After TrackKnownAxes: a move that extrudes while an axis is still unknown (an
  // absolute move naming X and Y only, after probing: Prusa's "G80" then "G1 X60 E9")
  // lays its bead at the last known coordinate of that axis, with a warning (a prime in
  // place lays none).
  void WarnBeadAtUnknown(const std::string& command, double extruded_mm, double xy_length_mm);
  // M101 ... M103 (extruder on, off) around moves without E: the 3D-era RepRap and
  // MakerBot form (Skeinforge for the Thing-O-Matic), fed at the firmware's M108 speed.
  // Such moves lay no bead (the amount is not in the file): warned, counted.
  void ExtruderOnWithoutE();
  bool extruder_on_ = false;  // between M101 and M103
  bool e_word_seen_ = false;  // a G0-G3 with E, A or B read
  void NoteEWords() { e_word_seen_ = e_word_seen_ || ExtruderWord(); }
  // Whether the line names an extruder axis: E, or A or B while they are extruders.
  bool ExtruderWord() const { return Find('E') || (ABAreExtruders() && (Find('A') || Find('B'))); }
  bool ABAreExtruders() const { return extruder_axes_ != ExtruderAxes::kABExtra; }
  // Where the logical position of extruder word k (0 E, 1 A, 2 B) is kept (e_logical_mm_).
  int ExtruderSlot(int k) const {
    return k == 0 && extruder_axes_ == ExtruderAxes::kEIsActiveAB ? (active_tool_ == 1 ? 2 : 1) : k;
  }
  // S on a G0-G3: S0 is ignored (a laser's power off, no endstop check: nothing in any
  // firmware's reading); after M3/M4 any S is the laser's power or spindle's speed,
  // ignored and warned; another S is refused, naming its meanings.
  void MoveS(const std::string& command);
  std::string spindle_on_since_;  // "M3 (line 12)": the first M3/M4 (spindle or laser on)
  // Counts a G0-G3's extruder words for RereadAs.
  void NoteExtruderAxes();
  ExtruderAxes extruder_axes_ = ExtruderAxes::kSeparate;
  bool ab_named_ = false;   // A or B on a G0-G3 (not G92: "G92 A0 B0" in a start script moves nothing)
  size_t xy_moves_e_ = 0;   // G0-G3 with X or Y and E
  size_t xy_moves_ab_ = 0;  // G0-G3 with X or Y and A or B
  bool e_on_move_ = false;  // E on a G0-G3
  // MakerBot's convention (GPX: A is tool 0's axis, B tool 1's), which QIDI's printers
  // keep: B named on a G0-G3, and every A while T0 is active and every B while T1 is.
  bool b_on_move_ = false;
  bool ab_off_their_tool_ = false;
  int m101_line_ = 0;
  // U, V, W, C words (a tool changer's coupler, a second carriage, a rotary axis; A and
  // B too where they are no extruders): not
  // modelled, ignored with a warning; one that moves while the line extrudes is an
  // error, since it would change the printed path.
  // `use`: a move's words (relative under G91), G92's (set) or G28's (homed to 0;
  // W is no axis for G28, see Home). Returns whether the line named any.
  enum class ExtraAxesUse { kMove, kSet, kHome };
  bool ExtraAxes(const std::string& command, double extruded_mm, ExtraAxesUse use = ExtraAxesUse::kMove);
  // Firmware retraction (G10/G11) and its settings (M207).
  // `swap`: Marlin's G10 S1 (a long retraction before a tool swap; G11 recovers it).
  void FirmwareRetract(bool retract, bool swap = false);
  void RetractSettings();
  // Klipper's SET_RETRACTION RETRACT_LENGTH= RETRACT_SPEED= UNRETRACT_EXTRA_LENGTH=
  // UNRETRACT_SPEED= (mm, mm/s; Kalico's Z_HOP_HEIGHT= too); `params` after the name.
  void KlipperRetractSettings(std::string_view params);
  // Klipper's SET_GCODE_OFFSET X= Y= Z= (or X_ADJUST= ...; mm): later absolute moves
  // land that much further; MOVE=1 moves there now (at MOVE_SPEED mm/s, else the feed).
  void KlipperGcodeOffset(std::string_view params);
  double klipper_offset_mm_[3] = {0, 0, 0};
  Eigen::Vector3d babystep_mm_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d work_offset_mm_[9];  // G54, ..., G59, G59.1-G59.3 (machine mm)
  int work_system_ = 0;
  Eigen::Vector3d saved_g92_mm_ = Eigen::Vector3d::Zero();  // G92.2's, for G92.3
  bool machine_coordinates_ = false;                        // G53 on this line
  // Marlin's M208 (S extra length, F feed on recovery); RepRapFirmware's M208 sets axis
  // limits (X, Y, Z... words) and is skipped.
  void RecoverSettings();
  // M220 S: feed rate percentage (B saves it, R restores: Marlin); M221 S: flow
  // percentage, scaling the E of G0-G3 (Marlin, RepRapFirmware, Klipper).
  void SpeedFactor();
  void FlowFactor();
  // M200 D (filament diameter; D0 off) and S (0 off, 1 on): E in cubic millimetres.
  void VolumetricExtrusion();
  // Checks a line's checksum ("N12 G1 X5*57": XOR of the bytes before '*'; the
  // number runs to `end`, the line's ';' comment or npos).
  void CheckChecksum(std::string_view line, size_t star, size_t end);
  // Layers from the heights at which the path extrudes, for files without layer comments.
  void LayersFromZ();
  // The feed rate of a G0-G3 move: the modal F, or before any F the firmware's
  // power-on rate (such moves are counted for a note).
  double MoveFeed(double length_mm, double extruded_mm);
  // Appends a segment from the current position to `end` (machine mm) and advances
  // the state; `geometry` completes arc fields. Returns nothing when nothing moves.
  void AddSegment(int gcode, const Eigen::Vector3d& end_mm, double extruded_mm, double length_mm,
                  double xy_length_mm, const ToolpathSegment* arc, double feed_mm_s);
  // E is relative under G91 and after M83 (until M82): Klipper's rule. Marlin's G90 and
  // G91 also cancel an earlier M82/M83 (the last of the four holds); the two differ
  // only where a file gives G90 after M83 without M83 again (relative under Klipper,
  // absolute under Marlin), which slicers' templates avoid by repeating M83.
  bool ERelative() const { return xyz_relative_ || e_mode_ == EMode::kRelative; }
  // Target machine position from X/Y/Z words (absolute or relative).
  Eigen::Vector3d Target() const;
  // The filament fed by the line's extruder word: E, or A or B (the extruder axes of
  // Cura's and PrusaSlicer's Mach3 and Machinekit flavours, MakerBot's two extruders),
  // each axis with its own position; two of them on one line are an error.
  double Extruded();

  std::string name_;
  int line_no_ = 0;
  Toolpath path_;
  std::vector<Word> words_;

  Eigen::Vector3d pos_mm_ = Eigen::Vector3d::Zero();     // machine position
  Eigen::Vector3d offset_mm_ = Eigen::Vector3d::Zero();  // machine = logical + offset (G92)
  double e_logical_mm_[3] = {0, 0, 0};  // E, A, B
  // Volumetric extrusion (M200): E words are mm^3 of this diameter's filament (0: off).
  double volumetric_diameter_mm_ = 0;
  bool volumetric_ = false;
  double feed_mm_s_ = 0;  // 0: none given yet
  double speed_factor_ = 1, saved_speed_factor_ = 1;  // M220 (and its B backup)
  std::map<int, double> flow_factor_;                 // M221 per tool (absent: 100 %)
  int active_tool_ = 0;                               // the last T n (or M6, M108, M135 T n)
  double retracted_mm_ = 0;  // the active tool's filament drawn back since it last laid plastic (ToolpathSegment::laid_m)
  std::map<int, double> parked_retraction_mm_;  // each other tool's, when it was parked (SelectTool)
  bool new_tool_unprimed_ = false;  // a tool change since the last bead: feeds in place refill the nozzle (SelectTool)
  double unit_mm_ = 1;    // 25.4 under G20
  bool xyz_relative_ = false;
  enum class EMode { kNone, kAbsolute, kRelative } e_mode_ = EMode::kNone;  // the last M82/M83
  int plane_ = 17;  // G17 XY, G18 ZX, G19 YZ
  bool axis_known_[3] = {true, true, true};  // false after probing, until an absolute move
  std::string unknown_since_;                // "G29 (line 12)": what made the position unknown
  double extra_axes_[6] = {0, 0, 0, 0, 0, 0};  // U, V, W, C (and A, B if not extruders) as the file sets them (file units)
  std::string extra_axes_seen_;              // the extra axes named in the file, in order of appearance
  int commands_on_line_ = 0;
  int layer_ = ToolpathSegment::kNoLayer;
  bool layer_comments_ = false;  // any layer comment seen
  int type_ = -1;
  double stated_height_m_ = 0;  // the height the file states for the moves that follow (0: none)
  double t_s_ = 0;
  // Firmware retraction's settings (mm, mm/s), as M207, M208 or Klipper's SET_RETRACTION
  // set them, else Marlin's defaults; the swap retraction's (Marlin's G10 S1 on a
  // multi-extruder printer: M207 W, M208 W and R; RETRACT_LENGTH_SWAP 13 mm,
  // RETRACT_RECOVER_LENGTH_SWAP 0, RETRACT_RECOVER_FEEDRATE_SWAP 8 mm/s).
  struct FwRetraction {
    double length_mm = 3.0;
    double feed_mm_s = 45.0;
    double recover_extra_mm = 0.0;
    double recover_feed_mm_s = 8.0;
    double hop_mm = 0.0;
    double swap_length_mm = 13.0;
    double swap_recover_extra_mm = 0.0;
    double swap_recover_feed_mm_s = 8.0;
  };
  FwRetraction fw_;                         // every tool's (M207 without P, Marlin, Klipper)
  std::map<int, FwRetraction> fw_of_tool_;  // RepRapFirmware's "M207 P1 ...": tool 1's own
  FwRetraction& FwSettings(std::optional<int> tool);  // tool's (none: every tool's)
  // Whether a tool is retracted by G10 (1) or by a swap retraction G10 S1 (2), per tool
  // as Marlin (retracted[], retracted_swap[]) and RepRapFirmware (Tool::isRetracted)
  // keep it; Klipper's firmware_retraction keeps one state (tool 0's key here).
  std::map<int, int> fw_state_;
  int FwStateKey() const { return klipper_ ? 0 : active_tool_; }
  // The Z hop is one for the machine (Marlin's current_hop): a G10 of a second tool
  // while the first one's hop holds lifts no further.
  double fw_hop_applied_mm_ = 0.0;
  // The file is for Klipper: its flavour says so (";FLAVOR:Klipper", a PrusaSlicer or
  // OrcaSlicer "; gcode_flavor = klipper"), or one of Klipper's own extended commands
  // was read. Then "T1" is the printer's macro, read as ACTIVATE_EXTRUDER, and firmware
  // retraction keeps one state.
  bool klipper_ = false;
};

}  // namespace gcode_detail
}  // namespace lt

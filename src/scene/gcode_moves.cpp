// The G-code reader's motion: G0/G1 moves, G2/G3 arcs, G4 dwell, G28 home, the feed
// rate, and the timed segments they append to the toolpath (what the extruder words
// feed: scene/gcode_extrusion.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "scene/gcode_reader.h"

namespace lt {
namespace gcode_detail {

namespace {

// Marlin's default homing speeds (HOMING_FEEDRATE_MM_M: 50 mm/s for X and Y, 4 mm/s for Z).
constexpr double kHomingFeedMmS[3] = {50.0, 50.0, 4.0};
// Marlin's feed rate at power-on (1500 mm/min), for moves before the file's first F.
constexpr double kPowerOnFeedMmS = 25.0;
// An arc's end may lie off its circle by this much (rounding of I/J and X/Y).
constexpr double kArcRadiusToleranceMm = 0.01;
constexpr double kArcRadiusToleranceRel = 1e-3;
// A feed that leaves less than this (mm) beyond making up a retraction lays nothing:
// the rounding of the E words that drew the filament back and fed it again (each
// written to 1e-5 mm: a wipe's pieces in M83, absolute E differences), kept below
// the 0.001 mm the warnings show.
constexpr double kRoundingMm = 5e-4;
// End points closer than this (mm) are the same point (full circles).
constexpr double kSamePointMm = 1e-9;
// The most turns an arc's P may ask for (Marlin's ARC_P_CIRCLES takes up to 100).
constexpr double kMaxArcTurns = 100;

// Angle wrapped into (0, 2 pi].
double WrapPositive(double a) {
  a = std::fmod(a, 2 * M_PI);
  if (a <= 0) a += 2 * M_PI;
  return a;
}

// Lengths in messages: up to 6 significant digits ("10", "0.0005").
std::string FormatLength(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

void GcodeReader::SetFeed() {
  if (const Word* f = Find('F')) {
    if (!(*f->value > 0)) Fail("feed rate F must be > 0, got " + FormatNumber(*f->value));
    feed_mm_s_ = *f->value * unit_mm_ / 60.0;
  }
}

Eigen::Vector3d GcodeReader::Target() const {
  Eigen::Vector3d target = pos_mm_;
  const char axes[3] = {'X', 'Y', 'Z'};
  for (int i = 0; i < 3; ++i) {
    if (const Word* w = Find(axes[i])) {
      double v = *w->value * unit_mm_;
      // G53: machine coordinates for this line's move (no G92 or work offset).
      target[i] = xyz_relative_ ? pos_mm_[i] + v : v + (machine_coordinates_ ? PhysicalOffset()[i] : offset_mm_[i]);
      // No machine reaches 1 km: such a number is a corrupted one, and its squares
      // and durations would overflow.
      if (!(std::abs(target[i]) <= kMaxCoordinateMm)) {
        Fail(std::string(1, axes[i]) + FormatNumber(*w->value) + " puts the nozzle at " + FormatNumber(target[i]) +
             " mm, beyond any machine's reach (1 km): a corrupted number?");
      }
    }
  }
  return target;
}

void GcodeReader::MoveS(const std::string& command) {
  const Word* s = Find('S');
  if (s && *s->value != 0 && !spindle_on_since_.empty()) {
    // After M3/M4 (a laser or spindle head: Marlin's laser mode with inline power, Grbl,
    // LightBurn's and LaserGRBL's "G1 X10 Y5 S255"), S is the head's power or speed.
    WarnOncePerName("S on moves", command + " S" + FormatNumber(*s->value) + ": a laser's power or a spindle's "
                    "speed, since " + spindle_on_since_ + " turned one on; ignored (a move without E lays no bead)");
    return;
  }
  if (s && *s->value != 0) {
    Fail(command + " S" + FormatNumber(*s->value) +
         " is not supported: on a move S is a laser power or spindle speed (Marlin's laser mode, Grbl) or, in "
         "older RepRapFirmware and Repetier, an endstop mode (RepRapFirmware's S1 as H1, S2 as H2); S0, none of "
         "them, is ignored");
  }
}

void GcodeReader::AddSegment(int gcode, const Eigen::Vector3d& end_mm, double extruded_mm, double length_mm,
                             double xy_length_mm, const ToolpathSegment* arc, double feed_mm_s) {
  double duration = 0;
  if (length_mm > 0) {
    duration = length_mm / feed_mm_s;
  } else if (extruded_mm != 0) {
    duration = std::abs(extruded_mm) / feed_mm_s;
  }
  if (duration > 0) {
    ToolpathSegment s = arc ? *arc : ToolpathSegment{};
    s.start_m = pos_mm_ * kMetresPerMm;
    s.end_m = end_mm * kMetresPerMm;
    s.extruded_m = extruded_mm * kMetresPerMm;
    // A feed first makes up what was drawn back; the rest leaves the nozzle.
    if (extruded_mm < 0) {
      retracted_mm_ -= extruded_mm;
    } else {
      // After a tool change, feeds in place until the tool's first bead refill its nozzle.
      const bool refill = new_tool_unprimed_ && !(xy_length_mm > 0);
      if (extruded_mm > 0 && xy_length_mm > 0) new_tool_unprimed_ = false;
      const double made_up_mm = refill ? extruded_mm : std::min(extruded_mm, retracted_mm_);
      retracted_mm_ = std::max(0.0, retracted_mm_ - made_up_mm);
      // What is left of a prime that makes up its retraction by the file's numbers is
      // the rounding of its E words (absolute E differences: "E2.42602" -> "E1.42602",
      // "G92 E0", "E1" leave 4e-16 mm; a wipe retracting in rounded pieces, then fed
      // back in one, 1e-5 mm): nothing. A feed with no retraction to make up lays all.
      const double laid_mm = extruded_mm - made_up_mm;
      s.laid_m = made_up_mm > 0 && laid_mm < kRoundingMm ? 0 : laid_mm * kMetresPerMm;
    }
    s.feed_m_s = feed_mm_s * kMetresPerMm;
    s.t_start_s = t_s_;
    s.t_end_s = t_s_ + duration;
    s.length_m = length_mm * kMetresPerMm;
    s.xy_length_m = xy_length_mm * kMetresPerMm;
    s.layer = layer_;
    s.type = type_;
    s.height_m = stated_height_m_;
    s.gcode = gcode;
    s.line = line_no_;
    path_.segments.push_back(s);
    t_s_ = s.t_end_s;
  }
  pos_mm_ = end_mm;
}

double GcodeReader::MoveFeed(double length_mm, double extruded_mm) {
  // M220's percentage scales every G0-G3 feed rate, as the firmware does.
  if (feed_mm_s_ > 0) return feed_mm_s_ * speed_factor_;
  if (length_mm > 0 || extruded_mm != 0) {
    if (path_.moves_at_power_on_feed++ == 0) path_.first_power_on_feed_line = line_no_;
  }
  return kPowerOnFeedMmS * speed_factor_;
}

void GcodeReader::SpeedFactor() {
  Expect("SBR", "M220");
  if (Find('B')) saved_speed_factor_ = speed_factor_;
  if (Find('R')) speed_factor_ = saved_speed_factor_;
  if (const Word* s = Find('S')) {
    if (!s->value || !(*s->value > 0)) Fail("M220 S (feed rate percentage) must be > 0");
    speed_factor_ = *s->value / 100.0;
  }
}

void GcodeReader::Move(int gcode) {
  Expect("XYZEFHABUVWCS", CommandName('G', gcode));
  MoveS(CommandName('G', gcode));
  // RepRapFirmware's H: 0 an ordinary move; 2 moves the motors without kinematics
  // (homing files lift Z so before the position is known; on the Cartesian printers
  // modelled here, the same motion as the axes' move); 1, 3 and 4 move towards the
  // endstops and stop where they trigger, homing the axes named.
  int h_mode = 0;
  if (const Word* h = Find('H')) {
    if (*h->value != std::floor(*h->value) || *h->value < 0 || *h->value > 4) {
      Fail(CommandName('G', gcode) + " H must be 0, 1, 2, 3 or 4 (RepRapFirmware's move modes), got " +
           FormatNumber(*h->value));
    }
    h_mode = int(*h->value);
    if (h_mode != 0 && ExtruderWord()) {
      Fail(CommandName('G', gcode) + " H" + std::to_string(h_mode) +
           " with E is not supported: H1-H4 are RepRapFirmware's homing and motor moves, not print moves");
    }
  }
  SetFeed();
  if (h_mode == 1 || h_mode == 3 || h_mode == 4) {
    // Towards the endstop: the move ends where the axis homes, taken as 0 as G28 does
    // (its length is not what the line asks, which only has to reach beyond the
    // endstop); at the line's feed rate.
    Eigen::Vector3d end = pos_mm_;
    const char axes[3] = {'X', 'Y', 'Z'};
    for (int k = 0; k < 3; ++k) {
      if (Find(axes[k])) {
        end[k] = 0;
        HomeAxis(k);
      }
    }
    ExtraAxes(CommandName('G', gcode), 0);
    double length = (end - pos_mm_).norm();
    AddSegment(28, end, 0, length, (end - pos_mm_).head<2>().norm(), nullptr, MoveFeed(length, 0));
    return;
  }
  TrackKnownAxes(CommandName('G', gcode), 0);
  NoteExtruderAxes();
  Eigen::Vector3d end = Target();
  double extruded = Extruded();
  WarnBeadAtUnknown(CommandName('G', gcode), extruded, (end - pos_mm_).head<2>().norm());
  // A file with E words (Skeinforge's and Simplify3D's 5D files keep M101/M103 around
  // them) is not of that form: only one whose moves never give E is warned (Finish
  // drops the warning of a file that gives E anywhere).
  NoteEWords();
  if (extruder_on_ && (end - pos_mm_).head<2>().norm() > 0 && !ExtruderWord()) {
    ExtruderOnWithoutE();
  }
  ExtraAxes(CommandName('G', gcode), extruded);
  double length = (end - pos_mm_).norm();
  AddSegment(gcode, end, extruded, length, (end - pos_mm_).head<2>().norm(), nullptr, MoveFeed(length, extruded));
}

void GcodeReader::Arc(int gcode) {
  const std::string command = CommandName('G', gcode);
  // The plane's axes p, q (the arc turns from p towards q when counter-clockwise) and
  // their centre offsets: G17 XY with I J, G18 ZX with K I, G19 YZ with J K (RS-274,
  // Marlin's CNC_WORKSPACE_PLANES); the third axis moves linearly (a helix).
  const int p = plane_ == 17 ? 0 : plane_ == 18 ? 2 : 1;
  const int q = plane_ == 17 ? 1 : plane_ == 18 ? 0 : 2;
  const char offset_p = "IJK"[p], offset_q = "IJK"[q];
  Expect(std::string("XYZEFRPABUVWCS") + offset_p + offset_q, command);
  MoveS(command);
  const std::string offsets = std::string(1, offset_p) + "/" + offset_q;
  const Word* i = Find(offset_p);
  const Word* j = Find(offset_q);
  const Word* r = Find('R');
  if (!i && !j && !r) Fail(command + " needs " + offsets + " (centre offset) or R (radius)");
  if ((i || j) && r) Fail(command + " takes " + offsets + " or R, not both");
  SetFeed();
  NoteEWords();
  NoteExtruderAxes();
  TrackKnownAxes(command, (1 << p) | (1 << q));
  Eigen::Vector3d end = Target();
  Eigen::Vector2d start2(pos_mm_[p], pos_mm_[q]), end2(end[p], end[q]);
  const bool clockwise = gcode == 2;
  Eigen::Vector2d centre;
  bool full_circle = false;
  if (r) {
    double radius = *r->value * unit_mm_;
    if (radius == 0) Fail(command + " with zero radius R");
    Eigen::Vector2d chord = end2 - start2;
    double d = chord.norm();
    if (d <= kSamePointMm) Fail(command + " with R needs an end point away from the start (use I/J for a full circle)");
    double half = d / 2;
    double excess = half - std::abs(radius);
    if (excess > std::max(kArcRadiusToleranceMm, kArcRadiusToleranceRel * half)) {
      Fail(command + " radius " + FormatLength(std::abs(radius) / unit_mm_) + " is too small for a chord of " +
           FormatLength(d / unit_mm_));
    }
    double h = std::sqrt(std::max(0.0, radius * radius - half * half));
    Eigen::Vector2d left(-chord.y() / d, chord.x() / d);
    // The shorter arc (R > 0) of a counter-clockwise move turns about a centre on
    // the left of the chord; clockwise or R < 0 puts it on the right.
    double side = (clockwise ? -1.0 : 1.0) * (radius > 0 ? 1.0 : -1.0);
    centre = start2 + chord / 2 + side * h * left;
  } else {
    Eigen::Vector2d offset(i ? *i->value * unit_mm_ : 0.0, j ? *j->value * unit_mm_ : 0.0);
    if (offset.norm() == 0) Fail(command + " with zero radius (" + offset_p + " and " + offset_q + " are 0)");
    centre = start2 + offset;
    full_circle = (end2 - start2).norm() <= kSamePointMm;
  }
  double r0 = (start2 - centre).norm();
  double r1 = (end2 - centre).norm();
  if (r0 == 0) Fail(command + " with zero radius");
  if (!(centre.norm() + r0 <= kMaxCoordinateMm)) {
    Fail(command + " radius " + FormatLength(r0 / unit_mm_) +
         " takes the arc beyond any machine's reach (1 km from the origin): a corrupted number?");
  }
  if (std::abs(r1 - r0) > std::max(kArcRadiusToleranceMm, kArcRadiusToleranceRel * r0)) {
    Fail(command + " end point is not on the arc: radius " + FormatLength(r0 / unit_mm_) + " at the start, " +
         FormatLength(r1 / unit_mm_) + " at the end");
  }
  double a0 = std::atan2(start2.y() - centre.y(), start2.x() - centre.x());
  double a1 = std::atan2(end2.y() - centre.y(), end2.x() - centre.x());
  double sweep = full_circle ? 2 * M_PI : WrapPositive(clockwise ? a0 - a1 : a1 - a0);
  // P: the number of turns (LinuxCNC, RepRapFirmware, Bambu Studio's and OrcaSlicer's
  // spiral lift "G2 Z.. I.. J.. P1"): P1 is the arc as given, each more adds a full turn.
  if (const Word* p = Find('P')) {
    if (!(*p->value >= 1) || *p->value != std::floor(*p->value) || *p->value > kMaxArcTurns) {
      Fail(command + " P (turns) must be a whole number from 1 to " + std::to_string(int(kMaxArcTurns)) + ", got " +
           FormatNumber(*p->value));
    }
    sweep += (*p->value - 1) * 2 * M_PI;
  }
  if (clockwise) sweep = -sweep;
  if (full_circle) r1 = r0;
  ToolpathSegment arc;
  arc.arc = true;
  arc.centre_m = centre * kMetresPerMm;
  arc.radius_start_m = r0 * kMetresPerMm;
  arc.radius_end_m = r1 * kMetresPerMm;
  arc.angle_start_rad = a0;
  arc.sweep_rad = sweep;
  double plane_length = 0.5 * (r0 + r1) * std::abs(sweep);
  const int l = 3 - p - q;
  double length = std::hypot(plane_length, end[l] - pos_mm_[l]);
  double extruded = Extruded();
  WarnBeadAtUnknown(command, extruded, plane_ == 17 ? plane_length : (end - pos_mm_).head<2>().norm());
  ExtraAxes(command, extruded);
  const double feed = MoveFeed(length, extruded);
  if (plane_ == 17) {
    AddSegment(gcode, end, extruded, length, plane_length, &arc, feed);
    return;
  }
  // Outside the bed plane (the toolpath's arcs lie in it): straight chords, as the
  // firmware runs them, each off the arc by at most kChordSagittaMm.
  const double r_max = std::max(r0, r1);
  const double step = r_max > kChordSagittaMm ? 2 * std::acos(1 - kChordSagittaMm / r_max) : M_PI / 2;
  const int chords = int(std::min(kMaxChords, std::max(1.0, std::ceil(std::abs(sweep) / step))));
  const Eigen::Vector3d start = pos_mm_;
  for (int k = 1; k <= chords; ++k) {
    const double u = double(k) / chords;
    Eigen::Vector3d point = end;
    if (k < chords) {
      const double a = a0 + u * sweep, radius = r0 + u * (r1 - r0);
      point[p] = centre.x() + radius * std::cos(a);
      point[q] = centre.y() + radius * std::sin(a);
      point[l] = start[l] + u * (end[l] - start[l]);
    }
    const Eigen::Vector3d step_vector = point - pos_mm_;
    AddSegment(gcode, point, extruded / chords, step_vector.norm(), step_vector.head<2>().norm(), nullptr, feed);
  }
}

void GcodeReader::Dwell() {
  Expect("PS", "G4");
  double seconds = 0;
  if (const Word* p = Find('P')) seconds += *p->value / 1000.0;
  if (const Word* s = Find('S')) seconds += *s->value;
  if (seconds < 0) Fail("G4 dwell time must be >= 0, got " + FormatNumber(seconds) + " s");
  if (seconds > 0) AddDwell(seconds);
}

void GcodeReader::AddDwell(double seconds) {
  ToolpathSegment s;
  s.start_m = s.end_m = pos_mm_ * kMetresPerMm;
  s.t_start_s = t_s_;
  s.t_end_s = t_s_ + seconds;
  s.layer = layer_;
  s.type = type_;
  s.gcode = 4;
  s.line = line_no_;
  path_.segments.push_back(s);
  t_s_ = s.t_end_s;
}

void GcodeReader::Home() {
  // The axes home one after another, X, Y then Z (Marlin's order, and the usual
  // homing files of RepRapFirmware and Klipper), each at its homing speed, whatever
  // the modal F (which G28 leaves as it was). Home is taken as 0; the nozzle starts
  // at the origin, so a G28 before any move takes no time. Extra axes named alone
  // ("G28 U", a tool changer's coupler) home only those (not modelled); W is no axis
  // here: Prusa firmware's "G28 W" homes all axes without mesh levelling.
  const bool any = Find('X') || Find('Y') || Find('Z');
  const bool extra = ExtraAxes("G28", 0, ExtraAxesUse::kHome);
  const char axes[3] = {'X', 'Y', 'Z'};
  for (int k = 0; k < 3; ++k) {
    if ((any || extra) && !Find(axes[k])) continue;
    Eigen::Vector3d end = pos_mm_;
    end[k] = 0;
    HomeAxis(k);
    const double length = std::abs(pos_mm_[k]);
    AddSegment(28, end, 0, length, k < 2 ? length : 0.0, nullptr, kHomingFeedMmS[k]);
  }
}

}  // namespace gcode_detail
}  // namespace lt

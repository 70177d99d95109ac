#include "scene/gcode.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>

#include "core/error.h"
#include "scene/motion_text.h"

namespace lt {

namespace {

constexpr double kMetresPerMm = 1e-3;
constexpr double kHomingFeedMmS = 50.0;  // Marlin's default homing speed
// Marlin's feed rate at power-on (1500 mm/min), for moves before the file's first F.
constexpr double kPowerOnFeedMmS = 25.0;
// An arc's end may lie off its circle by this much (rounding of I/J and X/Y).
constexpr double kArcRadiusToleranceMm = 0.01;
constexpr double kArcRadiusToleranceRel = 1e-3;
// End points closer than this (mm) are the same point (full circles).
constexpr double kSamePointMm = 1e-9;

bool IsLetter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
char Upper(char c) { return (c >= 'a' && c <= 'z') ? char(c - 'a' + 'A') : c; }
bool IsNumberChar(char c) { return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+'; }
bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Angle wrapped into (0, 2 pi].
double WrapPositive(double a) {
  a = std::fmod(a, 2 * M_PI);
  if (a <= 0) a += 2 * M_PI;
  return a;
}

// "G1", "M83" (built by appending: GCC 12 warns falsely on "G" + std::string).
std::string CommandName(char letter, int n) {
  std::string name(1, letter);
  name.append(std::to_string(n));
  return name;
}

// Lengths in messages: up to 6 significant digits ("10", "0.0005").
std::string FormatLength(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

bool StartsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// One parameter word: a letter and (for most commands, required) a number.
struct Word {
  char letter = 0;
  std::optional<double> value;
};

class GcodeReader {
 public:
  explicit GcodeReader(const std::string& name) : name_(name) {}

  void ReadLine(std::string_view line, int line_no);
  // After M2/M30: the program has ended, later lines are not executed.
  bool Ended() const { return path_.program_end_line > 0; }
  Toolpath Finish();

 private:
  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(name_ + ":" + std::to_string(line_no_), message);
  }

  void Comment(std::string_view comment);
  std::optional<double> CommentNumber(std::string_view text, const char* what) const;
  // Splits the words after the command. `numbers_required`: every letter needs a number;
  // `t_parameter`: T is a parameter (M207's), not a tool change.
  void ReadWords(std::string_view code, size_t pos, bool numbers_required, bool t_parameter = false);
  const Word* Find(char letter) const;
  void Expect(std::string_view allowed, const std::string& command) const;

  void Move(int gcode);
  void Arc(int gcode);
  void Dwell();
  void Home();
  void SetPosition();
  void SetFeed();
  // Firmware retraction (G10/G11) and its settings (M207).
  void FirmwareRetract(bool retract);
  void RetractSettings();
  // Checks a line's checksum ("N12 G1 X5*57": XOR of the bytes before '*').
  void CheckChecksum(std::string_view line, size_t star);
  // Layers from the heights at which the path extrudes, for files without layer comments.
  void LayersFromZ();
  // The feed rate of a G0-G3 move: the modal F, or before any F the firmware's
  // power-on rate (such moves are counted for a note).
  double MoveFeed(double length_mm, double extruded_mm);
  // Appends a segment from the current position to `end` (machine mm) and advances
  // the state; `geometry` completes arc fields. Returns nothing when nothing moves.
  void AddSegment(int gcode, const Eigen::Vector3d& end_mm, double extruded_mm, double length_mm,
                  double xy_length_mm, const ToolpathSegment* arc, double feed_mm_s);
  bool ERelative() const { return e_mode_ == EMode::kFollow ? xyz_relative_ : e_mode_ == EMode::kRelative; }
  // Target machine position from X/Y/Z words (absolute or relative).
  Eigen::Vector3d Target() const;
  double ExtrudedFrom(const Word* e);

  std::string name_;
  int line_no_ = 0;
  Toolpath path_;
  std::vector<Word> words_;

  Eigen::Vector3d pos_mm_ = Eigen::Vector3d::Zero();     // machine position
  Eigen::Vector3d offset_mm_ = Eigen::Vector3d::Zero();  // machine = logical + offset (G92)
  double e_logical_mm_ = 0;
  double feed_mm_s_ = 0;  // 0: none given yet
  double unit_mm_ = 1;    // 25.4 under G20
  bool xyz_relative_ = false;
  enum class EMode { kFollow, kAbsolute, kRelative } e_mode_ = EMode::kFollow;
  bool xy_plane_ = true;
  int layer_ = ToolpathSegment::kNoLayer;
  bool layer_comments_ = false;  // any layer comment seen
  int type_ = -1;
  double t_s_ = 0;
  // Firmware retraction: length, feed rates, Z hop (mm, mm/s), as set by M207 or
  // Marlin's defaults; whether the filament is retracted and the nozzle lifted now.
  double fw_retract_mm_ = 3.0;
  double fw_retract_feed_mm_s_ = 45.0;
  double fw_recover_extra_mm_ = 0.0;
  double fw_recover_feed_mm_s_ = 8.0;
  double fw_hop_mm_ = 0.0;
  bool fw_retracted_ = false;
  double fw_hop_applied_mm_ = 0.0;
};

Toolpath GcodeReader::Finish() {
  if (!layer_comments_) LayersFromZ();
  return std::move(path_);
}

void GcodeReader::LayersFromZ() {
  // A layer begins at the first move that extrudes at a height above every height at
  // which the current layer has extruded (the end of a rising move counts: a spiral
  // stays one layer); it takes the moves since the previous layer's last extrusion.
  constexpr double kTolM = 1e-9;
  int layer = ToolpathSegment::kNoLayer;
  double top = 0;
  size_t first_free = 0;  // the first segment after the last extrusion
  auto& segs = path_.segments;
  for (size_t k = 0; k < segs.size(); ++k) {
    ToolpathSegment& s = segs[k];
    if (!s.LaysBead()) continue;
    const double z0 = s.start_m.z(), z1 = std::max(z0, s.end_m.z());
    if (layer == ToolpathSegment::kNoLayer || z0 > top + kTolM) {
      layer = layer == ToolpathSegment::kNoLayer ? 0 : layer + 1;
      if (layer == 0) first_free = k;  // moves before the first extrusion stay outside
      top = z1;
    } else {
      top = std::max(top, z1);
    }
    for (size_t j = first_free; j <= k; ++j) segs[j].layer = layer;
    first_free = k + 1;
  }
  for (size_t j = first_free; j < segs.size() && layer != ToolpathSegment::kNoLayer; ++j) segs[j].layer = layer;
  path_.layers_from_z = layer != ToolpathSegment::kNoLayer;
}

std::optional<double> GcodeReader::CommentNumber(std::string_view text, const char* what) const {
  auto v = ParseFiniteNumber(TrimBlanks(text));
  if (!v) Fail(std::string(what) + " comment without a number: \"" + std::string(text) + "\"");
  return v;
}

void GcodeReader::Comment(std::string_view comment) {
  std::string_view c = TrimBlanks(comment);
  auto next_layer = [this] {
    layer_comments_ = true;
    layer_ = layer_ == ToolpathSegment::kNoLayer ? 0 : layer_ + 1;
  };
  auto set_type = [this](std::string_view name) {
    std::string type(TrimBlanks(name));
    int index = path_.TypeIndex(type);
    if (index < 0) {
      index = int(path_.type_names.size());
      path_.type_names.push_back(type);
    }
    type_ = index;
  };
  if (StartsWith(c, "LAYER:")) {
    auto v = CommentNumber(c.substr(6), "LAYER");
    if (*v != std::floor(*v) || std::abs(*v) > 1e9) Fail("LAYER comment needs an integer, got " + FormatNumber(*v));
    layer_comments_ = true;
    layer_ = int(*v);
  } else if (c == "LAYER_CHANGE" || c == "CHANGE_LAYER") {
    next_layer();
  } else if (c.size() > 6 && StartsWith(c, "layer ") && c[6] >= '0' && c[6] <= '9') {
    next_layer();  // Simplify3D: "; layer 1, Z = 0.200" (counted from 1)
  } else if (StartsWith(c, "BEGIN_LAYER_OBJECT")) {
    // KISSlicer: "; BEGIN_LAYER_OBJECT z=0.20 z_thickness=0.20"
    next_layer();
    size_t at = c.find("z_thickness=");
    if (at != std::string_view::npos) {
      std::string_view v = c.substr(at + 12);
      v = v.substr(0, v.find(' '));
      path_.layer_height_m[layer_] = *CommentNumber(v, "z_thickness") * kMetresPerMm;
    }
  } else if (StartsWith(c, "TYPE:") || StartsWith(c, "FEATURE:") || StartsWith(c, "segType:")) {
    set_type(c.substr(c.find(':') + 1));  // Cura, PrusaSlicer; Bambu, Orca; CraftWare
  } else if (StartsWith(c, "feature ")) {
    set_type(c.substr(8));  // Simplify3D: "; feature outer perimeter"
  } else if (c.size() > 2 && c[0] == '\'' && c.find("',", 1) != std::string_view::npos) {
    set_type(c.substr(1, c.find("',", 1) - 1));  // KISSlicer: "; 'Perimeter Path', 1.2 [feed mm/s], ..."
  } else if (StartsWith(c, "HEIGHT:") || StartsWith(c, "LAYER_HEIGHT:")) {
    double h = *CommentNumber(c.substr(c.find(':') + 1), "HEIGHT");
    // Slicers' comments are in millimetres, whatever G20/G21 say.
    if (layer_ != ToolpathSegment::kNoLayer) path_.layer_height_m[layer_] = h * kMetresPerMm;
  } else if (StartsWith(c, "Layer height:")) {
    path_.header_layer_height_m = *CommentNumber(c.substr(13), "Layer height") * kMetresPerMm;
  } else if (StartsWith(c, "layer_height =")) {
    path_.header_layer_height_m = *CommentNumber(c.substr(14), "layer_height") * kMetresPerMm;
  } else if (StartsWith(c, "layer_thickness_mm =")) {  // KISSlicer
    path_.header_layer_height_m = *CommentNumber(c.substr(20), "layer_thickness_mm") * kMetresPerMm;
  } else if (StartsWith(c, "layerHeight,")) {  // Simplify3D's settings summary
    path_.header_layer_height_m = *CommentNumber(c.substr(12), "layerHeight") * kMetresPerMm;
  } else if (StartsWith(c, "filament_diameter =")) {
    std::string_view list = c.substr(19);  // "1.75" or "1.75,1.75" (one per extruder)
    path_.filament_diameter_m = *CommentNumber(list.substr(0, list.find(',')), "filament_diameter") * kMetresPerMm;
  } else if (StartsWith(c, "fiber_dia_mm =")) {  // KISSlicer
    path_.filament_diameter_m = *CommentNumber(c.substr(14), "fiber_dia_mm") * kMetresPerMm;
  } else if (StartsWith(c, "filamentDiameters,")) {  // Simplify3D: "1.75|1.75|..." (one per extruder)
    std::string_view list = c.substr(18);
    path_.filament_diameter_m = *CommentNumber(list.substr(0, list.find('|')), "filamentDiameters") * kMetresPerMm;
  }
}

void GcodeReader::ReadWords(std::string_view code, size_t pos, bool numbers_required, bool t_parameter) {
  words_.clear();
  while (pos < code.size()) {
    if (IsBlank(code[pos])) {
      ++pos;
      continue;
    }
    char letter = Upper(code[pos]);
    if (!IsLetter(letter)) Fail("expected a parameter letter, got \"" + std::string(code.substr(pos)) + "\"");
    ++pos;
    size_t start = pos;
    while (pos < code.size() && IsNumberChar(code[pos])) ++pos;
    std::string_view number = code.substr(start, pos - start);
    Word w;
    w.letter = letter;
    if (number.empty()) {
      std::string rest(code.substr(start, 3));
      for (char& ch : rest) ch = Upper(ch);
      if (rest == "NAN" || rest == "INF") Fail(std::string(1, letter) + " is not a finite number");
      if (numbers_required) Fail(std::string(1, letter) + " without a number");
    } else {
      w.value = ParseFiniteNumber(number);
      if (!w.value) Fail(std::string(1, letter) + " has a malformed number \"" + std::string(number) + "\"");
    }
    if (letter == 'G' || letter == 'M' || (letter == 'T' && !t_parameter)) Fail("one command per line: found " + std::string(1, letter) + " after the command");
    for (const Word& other : words_) {
      if (other.letter == letter) Fail(std::string(1, letter) + " given twice");
    }
    words_.push_back(w);
  }
}

const Word* GcodeReader::Find(char letter) const {
  for (const Word& w : words_) {
    if (w.letter == letter) return &w;
  }
  return nullptr;
}

void GcodeReader::Expect(std::string_view allowed, const std::string& command) const {
  for (const Word& w : words_) {
    if (allowed.find(w.letter) == std::string_view::npos) {
      Fail(command + " takes no parameter " + std::string(1, w.letter));
    }
  }
}

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
      target[i] = xyz_relative_ ? pos_mm_[i] + v : v + offset_mm_[i];
    }
  }
  return target;
}

double GcodeReader::ExtrudedFrom(const Word* e) {
  if (!e) return 0;
  double v = *e->value * unit_mm_;
  double delta = ERelative() ? v : v - e_logical_mm_;
  e_logical_mm_ = ERelative() ? e_logical_mm_ + v : v;
  return delta;
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
    s.feed_m_s = feed_mm_s * kMetresPerMm;
    s.t_start_s = t_s_;
    s.t_end_s = t_s_ + duration;
    s.length_m = length_mm * kMetresPerMm;
    s.xy_length_m = xy_length_mm * kMetresPerMm;
    s.layer = layer_;
    s.type = type_;
    s.gcode = gcode;
    s.line = line_no_;
    path_.segments.push_back(s);
    t_s_ = s.t_end_s;
  }
  pos_mm_ = end_mm;
}

double GcodeReader::MoveFeed(double length_mm, double extruded_mm) {
  if (feed_mm_s_ > 0) return feed_mm_s_;
  if (length_mm > 0 || extruded_mm != 0) {
    if (path_.moves_at_power_on_feed++ == 0) path_.first_power_on_feed_line = line_no_;
  }
  return kPowerOnFeedMmS;
}

void GcodeReader::Move(int gcode) {
  Expect("XYZEF", CommandName('G', gcode));
  SetFeed();
  Eigen::Vector3d end = Target();
  double extruded = ExtrudedFrom(Find('E'));
  double length = (end - pos_mm_).norm();
  AddSegment(gcode, end, extruded, length, (end - pos_mm_).head<2>().norm(), nullptr, MoveFeed(length, extruded));
}

void GcodeReader::Arc(int gcode) {
  const std::string command = CommandName('G', gcode);
  Expect("XYZEFIJR", command);
  if (!xy_plane_) Fail(command + " outside the XY plane (G18/G19) is not supported");
  const Word* i = Find('I');
  const Word* j = Find('J');
  const Word* r = Find('R');
  if (!i && !j && !r) Fail(command + " needs I/J (centre offset) or R (radius)");
  if ((i || j) && r) Fail(command + " takes I/J or R, not both");
  SetFeed();
  Eigen::Vector3d end = Target();
  Eigen::Vector2d start2 = pos_mm_.head<2>(), end2 = end.head<2>();
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
    if (offset.norm() == 0) Fail(command + " with zero radius (I and J are 0)");
    centre = start2 + offset;
    full_circle = (end2 - start2).norm() <= kSamePointMm;
  }
  double r0 = (start2 - centre).norm();
  double r1 = (end2 - centre).norm();
  if (r0 == 0) Fail(command + " with zero radius");
  if (std::abs(r1 - r0) > std::max(kArcRadiusToleranceMm, kArcRadiusToleranceRel * r0)) {
    Fail(command + " end point is not on the arc: radius " + FormatLength(r0 / unit_mm_) + " at the start, " +
         FormatLength(r1 / unit_mm_) + " at the end");
  }
  double a0 = std::atan2(start2.y() - centre.y(), start2.x() - centre.x());
  double a1 = std::atan2(end2.y() - centre.y(), end2.x() - centre.x());
  double sweep = full_circle ? 2 * M_PI : WrapPositive(clockwise ? a0 - a1 : a1 - a0);
  if (clockwise) sweep = -sweep;
  if (full_circle) r1 = r0;
  ToolpathSegment arc;
  arc.arc = true;
  arc.centre_m = centre * kMetresPerMm;
  arc.radius_start_m = r0 * kMetresPerMm;
  arc.radius_end_m = r1 * kMetresPerMm;
  arc.angle_start_rad = a0;
  arc.sweep_rad = sweep;
  double xy_length = 0.5 * (r0 + r1) * std::abs(sweep);
  double length = std::hypot(xy_length, end.z() - pos_mm_.z());
  double extruded = ExtrudedFrom(Find('E'));
  AddSegment(gcode, end, extruded, length, xy_length, &arc, MoveFeed(length, extruded));
}

void GcodeReader::Dwell() {
  Expect("PS", "G4");
  double seconds = 0;
  if (const Word* p = Find('P')) seconds += *p->value / 1000.0;
  if (const Word* s = Find('S')) seconds += *s->value;
  if (seconds < 0) Fail("G4 dwell time must be >= 0, got " + FormatNumber(seconds) + " s");
  if (seconds > 0) {
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
}

void GcodeReader::Home() {
  bool any = Find('X') || Find('Y') || Find('Z');
  Eigen::Vector3d end = pos_mm_;
  const char axes[3] = {'X', 'Y', 'Z'};
  for (int k = 0; k < 3; ++k) {
    if (!any || Find(axes[k])) {
      end[k] = 0;
      offset_mm_[k] = 0;
    }
  }
  double feed = feed_mm_s_ > 0 ? feed_mm_s_ : kHomingFeedMmS;
  AddSegment(28, end, 0, (end - pos_mm_).norm(), (end - pos_mm_).head<2>().norm(), nullptr, feed);
}

void GcodeReader::SetPosition() {
  Expect("XYZE", "G92");
  if (words_.empty()) {
    offset_mm_ = pos_mm_;
    e_logical_mm_ = 0;
    return;
  }
  const char axes[3] = {'X', 'Y', 'Z'};
  for (int k = 0; k < 3; ++k) {
    if (const Word* w = Find(axes[k])) offset_mm_[k] = pos_mm_[k] - *w->value * unit_mm_;
  }
  if (const Word* e = Find('E')) e_logical_mm_ = *e->value * unit_mm_;
}

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

void GcodeReader::CheckChecksum(std::string_view line, size_t star) {
  std::string_view digits = TrimBlanks(line.substr(star + 1));
  bool ok = !digits.empty() && digits.size() <= 3;
  for (char c : digits) ok = ok && c >= '0' && c <= '9';
  if (!ok) Fail("checksum after '*' must be a number 0-255, got \"" + std::string(digits) + "\"");
  int expected = std::stoi(std::string(digits));
  int sum = 0;
  for (char c : line.substr(0, star)) sum ^= static_cast<unsigned char>(c);
  if (sum != expected) {
    Fail("checksum *" + std::string(digits) + " does not match the line (its bytes before '*' give " +
         std::to_string(sum) + ")");
  }
}

void GcodeReader::ReadLine(std::string_view line, int line_no) {
  line_no_ = line_no;
  size_t semicolon = line.find(';');
  std::string_view code = line.substr(0, semicolon);
  // A checksum "*57" ends the code; it must match (a corrupted line is not read).
  if (size_t star = code.find('*'); star != std::string_view::npos) {
    CheckChecksum(code, star);
    code = code.substr(0, star);
  }
  // Parenthesised comments, then a checksum.
  std::string cleaned;
  if (code.find('(') != std::string_view::npos) {
    bool inside = false;
    for (char c : code) {
      if (c == '(') inside = true;
      if (!inside) cleaned += c;
      if (c == ')') inside = false;
    }
    code = cleaned;
  }
  code = TrimBlanks(code);
  if (code == "%") return;  // RS-274's program start and end mark
  if (code.empty()) {
    if (semicolon != std::string_view::npos) Comment(line.substr(semicolon + 1));
    return;
  }
  size_t pos = 0;
  // A line number "N123" first.
  if (Upper(code[0]) == 'N' && code.size() > 1 && code[1] >= '0' && code[1] <= '9') {
    ++pos;
    while (pos < code.size() && IsNumberChar(code[pos])) ++pos;
    while (pos < code.size() && IsBlank(code[pos])) ++pos;
    if (pos == code.size()) return;
  }
  // An extended command (Klipper's PRINT_START, EXCLUDE_OBJECT_START NAME=...,
  // SET_PRESSURE_ADVANCE ADVANCE=...): a name of letters, digits and
  // underscores that does not start with a letter and a number. Skipped, counted by name.
  if (pos + 1 < code.size() && IsLetter(code[pos]) && (IsLetter(code[pos + 1]) || code[pos + 1] == '_')) {
    size_t end = pos;
    while (end < code.size() && !IsBlank(code[end])) ++end;
    std::string name(code.substr(pos, end - pos));
    for (char& ch : name) ch = Upper(ch);
    ++path_.skipped_commands[name];
    return;
  }
  char letter = Upper(code[pos]);
  if (letter != 'G' && letter != 'M' && letter != 'T') {
    Fail("expected a command (G, M or T), got \"" + std::string(code.substr(pos)) + "\"");
  }
  size_t start = ++pos;
  while (pos < code.size() && IsNumberChar(code[pos])) ++pos;
  std::string_view number = code.substr(start, pos - start);
  if (number.empty()) Fail(std::string(1, letter) + " without a number");
  auto value = ParseFiniteNumber(number);
  if (!value) Fail(std::string(1, letter) + " has a malformed number \"" + std::string(number) + "\"");
  const bool integral = *value == std::floor(*value) && std::abs(*value) < 1e6;
  const int n = integral ? int(*value) : -1;
  if (letter == 'G' && integral) {
    switch (n) {
      case 0:
      case 1: ReadWords(code, pos, true); Move(n); return;
      case 2:
      case 3: ReadWords(code, pos, true); Arc(n); return;
      case 4: ReadWords(code, pos, true); Dwell(); return;
      case 10:
        ReadWords(code, pos, true);
        if (words_.empty()) {
          FirmwareRetract(true);
          return;
        }
        // With parameters: tool offsets and temperatures (RepRapFirmware's G10 P),
        // coordinate systems (G10 L), Marlin's swap retraction (G10 S1): skipped.
        ++path_.skipped_commands["G10"];
        return;
      case 11: ReadWords(code, pos, true); Expect("", "G11"); FirmwareRetract(false); return;
      case 17:
      case 18:
      case 19: ReadWords(code, pos, true); Expect("", CommandName('G', n)); xy_plane_ = n == 17; return;
      case 20:
      case 21: ReadWords(code, pos, true); Expect("", CommandName('G', n)); unit_mm_ = n == 20 ? 25.4 : 1.0; return;
      case 28: ReadWords(code, pos, false); Home(); return;
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
}

}  // namespace

Toolpath ParseGcode(std::string_view text, const std::string& display_name) {
  GcodeReader reader(display_name);
  size_t pos = StartsWith(text, "\xEF\xBB\xBF") ? 3 : 0;  // a UTF-8 byte order mark
  int line_no = 0;
  int after_end = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    ++line_no;
    if (!reader.Ended()) {
      reader.ReadLine(line, line_no);
    } else {
      // Lines after the program's end are not read; those holding more than blanks,
      // comments and "%" are counted.
      std::string_view code = TrimBlanks(line.substr(0, line.find(';')));
      if (!code.empty() && code != "%") ++after_end;
    }
    pos = end + 1;
  }
  Toolpath path = reader.Finish();
  path.lines_after_program_end = after_end;
  return path;
}

Toolpath ReadGcode(const std::filesystem::path& path, const std::string& display_name) {
  std::string name = display_name.empty() ? path.string() : display_name;
  return ParseGcode(ReadTextFile(path, name), name);
}

}  // namespace lt

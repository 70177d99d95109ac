// What a pose file's column names say (pose_file_names.h).
#include "pipeline/pose_file_names.h"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "core/text_fields.h"

namespace lt::pose_file_detail {

std::string NameAndUnit(std::string_view field, std::string* unit) {
  std::string name = Lower(TrimBlanks(field));
  unit->clear();
  for (auto [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    const size_t a = name.rfind(open);
    if (a != std::string::npos && !name.empty() && name.back() == close) {
      *unit = std::string(TrimBlanks(std::string_view(name).substr(a + 1, name.size() - a - 2)));
      name = std::string(TrimBlanks(std::string_view(name).substr(0, a)));
      return name;
    }
  }
  for (const char* u : {"_mm", "_m"}) {
    const std::string_view s(u);
    if (name.size() > s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0) {
      *unit = std::string(s.substr(1));
      return std::string(std::string_view(name).substr(0, name.size() - s.size()));
    }
  }
  return name;
}

int AxisAfter(const std::string& name, std::initializer_list<const char*> prefixes, const char* axes) {
  for (const char* p : prefixes) {
    const std::string_view ps(p);
    if (name.size() != ps.size() + 1 || name.compare(0, ps.size(), ps) != 0) continue;
    const char* hit = std::strchr(axes, name.back());
    if (hit && *hit) return int(hit - axes);
  }
  return -1;
}

double TimeColumn(const std::string& name, const std::string& unit, bool* known) {
  *known = true;
  for (const char* s : {"t", "time", "timestamp", "stamp"}) {
    if (name != s) continue;
    *known = !unit.empty();
    if (unit.empty() || unit == "s" || unit == "seconds") return 1.0;
    return unit == "ms" ? 1e-3 : unit == "us" ? 1e-6 : unit == "ns" ? 1e-9 : -1.0;
  }
  for (const char* s : {"t_s", "time_s", "timestamp_s"}) {
    if (name == s) return 1.0;
  }
  for (const char* s : {"t_ns", "time_ns", "timestamp_ns"}) {
    if (name == s) return 1e-9;
  }
  return 0;
}

bool Skipped(const std::string& name) {
  for (const char* s : {"", "frame", "index", "image", "file", "filename", "id", "name"}) {  // "": a trailing ','s column
    if (name == s) return true;
  }
  return false;
}

std::vector<std::string> Words(const std::string& name) {
  std::vector<std::string> words(1);
  for (char c : name) {
    if (c == '%') continue;
    if (c == '.' || c == '_' || c == '-' || c == ' ' || c == '/') {
      if (!words.back().empty()) words.emplace_back();
    } else {
      words.back() += c;
    }
  }
  if (words.back().empty()) words.pop_back();
  return words;
}

bool ChildFrame(const std::vector<std::string>& words) {
  const size_t n = words.size();
  if (n >= 3 && words[n - 3] == "child" && words[n - 2] == "frame" && words[n - 1] == "id") return true;
  return n >= 2 && words[n - 2] == "child" && words[n - 1] == "frame";
}

namespace {

// A word naming another quantity than the pose: velocities and accelerations, biases,
// covariances and twists (ROS's Odometry), forces, currents, joints, errors, and the
// message's bookkeeping (header.seq, frame_id). EuRoC's one-letter prefixes (v_RS_R_x,
// b_w_RS_S_x) only as the first word: "pose_b_x" may be a second pose. Not skipped: a
// tool, a work object or an external axis, which may change the pose's frame.
bool OtherQuantity(const std::string& w, bool first) {
  static const char* const kWords[] = {
      "vel",    "velocity", "speed",  "twist", "linear",  "angular", "acc",         "accel",        "acceleration",
      "bias",   "cov",      "force",  "torque", "wrench", "current", "voltage",     "temperature",  "temperatures",
      "error",  "std",      "sigma",  "var",   "variance", "seq",    "header",      "frame",        "id",
      "child",  "status",   "mode",   "joint", "qd",      "qdd",
      // ABB's robtarget beside the pose: its arm configuration, the move's instruction and zone
      "cf1",    "cf4",      "cf6",    "cfx",   "move",    "zone"};
  for (const char* k : kWords) {
    if (w == k) return true;
  }
  if (first && (w == "v" || w == "b")) return true;
  return w.rfind("covariance", 0) == 0;  // ROS's covariance0..35
}


Kind WordKind(const std::string& w) {
  for (const char* k : {"p", "pos", "position", "t", "trans", "translation"}) {
    if (w == k) return Kind::kTranslation;
  }
  for (const char* k : {"q", "quat", "quaternion", "orientation", "rotation"}) {
    if (w == k) return Kind::kQuaternion;
  }
  return Kind::kNone;
}

}  // namespace

bool OtherQuantity(const std::vector<std::string>& words) {
  for (size_t i = 0; i < words.size(); ++i) {
    if (OtherQuantity(words[i], i == 0)) return true;
  }
  return false;
}

Kind WordsKind(const std::vector<std::string>& words, int* axis) {
  if (words.size() < 2 || words.back().size() != 1) return Kind::kNone;
  const char* hit = std::strchr("xyzw", words.back()[0]);
  if (!hit || !*hit) return Kind::kNone;
  *axis = int(hit - "xyzw");
  if (OtherQuantity(words)) return Kind::kNone;
  const Kind first = WordKind(words.front()), last = WordKind(words[words.size() - 2]);
  const Kind kind = first == Kind::kNone ? last : first;
  if (last != Kind::kNone && last != kind) return Kind::kNone;
  if (kind == Kind::kTranslation && *axis == 3) return Kind::kNone;
  return kind;
}

// KUKA RSI's actual Cartesian pose (its RIst tag: X Y Z in mm, A B C in degrees) in a
// column name of two words, "X_RIst" or "RIst.X": 0..2 for X Y Z, 3..5 for A B C, -1
// otherwise. Its setpoint (RSol) and the log's other signals are skipped.
int RsiActual(const std::vector<std::string>& words) {
  if (words.size() != 2) return -1;
  const std::string& axis = words[0] == "rist" ? words[1] : words[1] == "rist" ? words[0] : std::string();
  if (axis.size() != 1) return -1;
  const char* hit = std::strchr("xyzabc", axis[0]);
  return hit && *hit ? int(hit - "xyzabc") : -1;
}

bool TimePart(const std::vector<std::string>& words, double* part, std::string* prefix) {
  if (words.empty()) return false;
  const std::string& last = words.back();
  if (last == "sec" || last == "secs") {
    *part = 1.0;
  } else if (last == "nanosec" || last == "nsec" || last == "nsecs") {
    *part = 1e-9;
  } else {
    return false;
  }
  // The stamp the two parts make: "secs" alone, or after a word naming a time.
  if (words.size() >= 2) {
    const std::string& before = words[words.size() - 2];
    if (before != "stamp" && before != "time" && before != "timestamp" && before != "t") return false;
  }
  prefix->clear();
  for (size_t i = 0; i + 1 < words.size(); ++i) *prefix += (i ? "." : "") + words[i];
  return true;
}

int FrankaPoseElement(const std::string& lower_field, bool* commanded) {
  std::string name(TrimBlanks(lower_field));
  // The element's index: "[k]", ".k", "_k" or digits right after the name (rostopic -p's "O_T_EE3").
  if (!name.empty() && name.back() == ']') {  // "o_t_ee[3]" reads as "o_t_ee3"
    const size_t open = name.rfind('[');
    if (open == std::string::npos) return -1;
    name = name.substr(0, open) + name.substr(open + 1, name.size() - open - 2);
  }
  size_t digits = name.size();
  while (digits > 0 && std::isdigit(static_cast<unsigned char>(name[digits - 1]))) --digits;
  if (digits == name.size() || name.size() - digits > 2) return -1;
  const int k = std::stoi(name.substr(digits));
  if (k > 15) return -1;
  std::string base = name.substr(0, digits);
  if (!base.empty() && (base.back() == '.' || base.back() == '_')) base.pop_back();
  *commanded = false;
  for (const char* suffix : {"_d", "_c"}) {
    if (base.size() > 2 && base.compare(base.size() - 2, 2, suffix) == 0) {
      base.resize(base.size() - 2);
      *commanded = true;
    }
  }
  const std::string pose = "o_t_ee";
  if (base.size() < pose.size() || base.compare(base.size() - pose.size(), pose.size(), pose) != 0) return -1;
  const size_t before = base.size() - pose.size();
  if (before > 0 && base[before - 1] != '.' && base[before - 1] != '/') return -1;
  *commanded |= base.compare(0, 4, "cmd.") == 0;
  return k;
}

bool QuaternionAngles(const std::vector<std::string>& words) {
  size_t n = words.size();
  if (n > 0 && (words[n - 1] == "deg" || words[n - 1] == "rad")) --n;
  if (n < 2 || (words[n - 1] != "roll" && words[n - 1] != "pitch" && words[n - 1] != "yaw")) return false;
  for (size_t i = 0; i + 1 < n; ++i) {
    if (words[i] == "orientation" || words[i] == "rotation" || words[i] == "quaternion") return true;
  }
  return false;
}

const char* ExportNotRead(const std::string& first) {
  if (first == "segments" || first == "trajectories") {
    return "a Vicon Nexus export (a section name, the rate, subject and unit rows above the column names) is not "
           "read: save the segment's rows under one header line naming them, its rotation as a quaternion (its RX RY "
           "RZ are angles in degrees; rx,ry,rz here are a rotation vector in radians), e.g. frame,qx,qy,qz,qw,"
           "x [mm],y [mm],z [mm]";
  }
  if (first == "no_of_frames" || first == "file_version") {
    return "a Qualisys QTM TSV export (NO_OF_FRAMES, DATA_INCLUDED ... rows above the column names) is not read: its "
           "Roll Pitch Yaw follow the Euler angle definition set in QTM's options, which the file does not say; save "
           "the body's rows under one header line naming them, its rotation as a quaternion, e.g. "
           "frame,x [mm],y [mm],z [mm],qx,qy,qz,qw";
  }
  if (!first.empty() && (first[0] == '{' || first[0] == '[')) {
    return "a JSON file is not read as poses (a nerfstudio or instant-ngp transforms.json holds camera-to-world "
           "matrices in OpenGL camera axes, y up and z backwards, not OpenCV's): write one row per frame, "
           "x,y,z,qx,qy,qz,qw of world_from_cam in OpenCV camera axes (x right, y down, z forward)";
  }
  return nullptr;
}

}  // namespace lt::pose_file_detail

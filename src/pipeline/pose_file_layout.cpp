// The layout of a pose file's columns (pose_file_layout.h): column names with their
// units, the header's layout, and the layout of rows without a header. Reading the rows
// into poses is in pose_file.cpp.
#include "pipeline/pose_file_layout.h"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "core/error.h"
#include "core/text_fields.h"

namespace lt::pose_file_detail {

std::string Lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

namespace {

// A column name without its unit ("x [mm]", "x (m)", "x_mm", "x_m"), lower case, and that unit.
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

// The axis (0, 1, 2, or 3 for w) a name ends with after one of the prefixes, or -1.
int AxisAfter(const std::string& name, std::initializer_list<const char*> prefixes, const char* axes) {
  for (const char* p : prefixes) {
    const std::string_view ps(p);
    if (name.size() != ps.size() + 1 || name.compare(0, ps.size(), ps) != 0) continue;
    const char* hit = std::strchr(axes, name.back());
    if (hit && *hit) return int(hit - axes);
  }
  return -1;
}

// A time column's name: its unit in seconds (the name's, else `unit`'s), 0 for
// another name, -1 for an unknown unit. `known`: the name gives the unit.
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

// The words of a name, split at '.', '_', '-', '/' and blanks ("field.pose.position.x",
// "p_RS_R_x", PlotJuggler's "/vicon/pose/position/x"); rostopic's '%' before "%time" dropped.
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

bool OtherQuantity(const std::vector<std::string>& words) {
  for (size_t i = 0; i < words.size(); ++i) {
    if (OtherQuantity(words[i], i == 0)) return true;
  }
  return false;
}

enum class Kind { kNone, kTranslation, kQuaternion };

Kind WordKind(const std::string& w) {
  for (const char* k : {"p", "pos", "position", "t", "trans", "translation"}) {
    if (w == k) return Kind::kTranslation;
  }
  for (const char* k : {"q", "quat", "quaternion", "orientation", "rotation"}) {
    if (w == k) return Kind::kQuaternion;
  }
  return Kind::kNone;
}

// A name of several words ending in an axis, its first or second-to-last word naming a
// position or a quaternion: EuRoC's "p_RS_R_x", "q_RS_w", ROS's "field.pose.position.x",
// "field.transform.rotation.w". The axis (0..2, 3 for w) and the kind; kNone when a word
// names another quantity or the two words disagree.
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

// Multi-row exports this reader does not take, by their first field.
const char* ExportNotRead(const std::string& first) {
  if (first == "segments" || first == "trajectories") {
    return "a Vicon Nexus export (a section name, the rate, subject and unit rows above the column names) is not "
           "read: save the segment's rows under one header line naming them, its rotation as a quaternion (its RX RY "
           "RZ are angles in degrees; rx,ry,rz here are a rotation vector in radians), e.g. frame,qx,qy,qz,qw,"
           "x [mm],y [mm],z [mm]";
  }
  return nullptr;
}

}  // namespace

// The layout a header names; nullopt when `strict` is false and a name is not known.
// Columns of other quantities (velocities, biases, covariances, ROS's bookkeeping, or
// any other field of a Universal Robots RTDE log) are skipped; another unknown name,
// one that might be a competing pose, is an error.
std::optional<Layout> HeaderLayout(const std::vector<std::string_view>& fields, const std::string& where, bool strict,
                                   std::optional<PoseUnits>* header_units) {
  Layout l;
  l.fields = fields.size();
  bool quat = false, abb = false, rotvec = false, kuka = false, fanuc = false;
  std::optional<std::string> t_unit;
  std::string names, used;
  int time_rank = -1;  // ROS: the message's header.stamp (2) before another time (1) before rosbag's %time (0)
  // A Universal Robots RTDE log or a KUKA RSI log: their other fields (joints, speeds,
  // the commanded pose, process signals) are skipped.
  // An RTDE log's pose is its actual_TCP_pose, else (a planned path) its target_TCP_pose.
  // Vicon's columns hold a "Sub Frame".
  bool actual_log = false, rtde_actual = false, vicon_columns = false;
  std::vector<size_t> unknown;
  for (std::string_view f : fields) {
    std::string unit;
    const std::string name = NameAndUnit(f, &unit);
    rtde_actual |= name.rfind("actual_tcp_pose_", 0) == 0;
    actual_log |= name.rfind("target_tcp_pose_", 0) == 0 || RsiActual(Words(name)) >= 0;
    vicon_columns |= name == "sub frame";
  }
  actual_log |= rtde_actual;
  const std::string rtde_pose = rtde_actual ? "actual_tcp_pose_" : "target_tcp_pose_";
  for (size_t i = 0; i < fields.size(); ++i) {
    std::string unit;
    const std::string name = NameAndUnit(fields[i], &unit);
    names += (i ? "," : "") + name;
    const int c = int(i);
    int a;
    auto fail = [&](const std::string& why) -> std::optional<Layout> {
      if (!strict) return std::nullopt;
      throw InputError(where, "column " + std::to_string(i + 1) + " '" + std::string(TrimBlanks(fields[i])) + "': " + why);
    };
    auto set = [&](int* slot) -> bool {
      if (*slot >= 0) return false;
      *slot = c;
      return true;
    };
    if (i == 0) {
      if (const char* why = ExportNotRead(name)) return fail(why);
    }
    if (ParseFiniteNumber(TrimBlanks(fields[i]))) {
      return fail("a number where a column's name belongs: rows of numbers and text need a header line naming the "
                  "columns (ros2 topic echo --csv writes none), e.g. header.stamp.sec,header.stamp.nanosec,"
                  "header.frame_id,x,y,z,qx,qy,qz,qw");
    }
    bool ok = true;
    if (Skipped(name)) continue;
    const std::vector<std::string> words = Words(name);
    bool known = false;
    double to_s = TimeColumn(name, unit, &known);
    int rank = 1;
    if (to_s == 0 && name == "%time") {  // rostopic echo -p: when rosbag recorded the message, ns
      to_s = 1e-9, known = true, rank = 0;
    } else if (to_s == 0 && name == "__time") {  // PlotJuggler's CSV export: seconds
      to_s = 1.0, known = true;
    } else if (to_s == 0 && words.size() >= 2 && words.back() == "stamp" && words[words.size() - 2] == "header") {
      to_s = 1e-9, known = true, rank = 2;  // ROS's field.header.stamp, ns
    }
    if (to_s != 0) {
      if (to_s < 0) return fail("unknown time unit '" + unit + "' (s, ms, us or ns)");
      if (rank == time_rank) return fail("a second time column");
      if (rank > time_rank) {
        time_rank = rank;
        l.time = c;
        l.time_to_s = to_s;
        l.time_unit_known = known;
      }
      continue;
    }
    const int kinds_before = int(quat) + int(abb) + int(rotvec) + int(kuka) + int(fanuc);
    Kind kind = Kind::kNone;
    int word_axis = -1;
    if (name.rfind(rtde_pose, 0) == 0 && name.size() == 17 && name[16] >= '0' && name[16] <= '5') {
      // Universal Robots' RTDE log: x y z in metres, then the rotation vector.
      const int k = name[16] - '0';
      ok = k < 3 ? set(&l.t[k]) : set(&l.r[k - 3]);
      rotvec |= k >= 3;
      if (k < 3 && !t_unit) t_unit = "m";
    } else if (const int k = RsiActual(words); k >= 0) {
      ok = k < 3 ? set(&l.t[k]) : set(&l.r[k - 3]);
      kuka |= k >= 3;
      if (k < 3 && !t_unit) t_unit = "mm";
    } else if ((a = AxisAfter(name, {"", "t", "t_", "p_", "pos_", "position_", "trans_", "translation_", "tcp_"}, "xyz")) >= 0 ||
               (kind = WordsKind(words, &word_axis)) == Kind::kTranslation) {
      if (a < 0) a = word_axis;
      ok = set(&l.t[a]);
      if (!unit.empty()) {
        if (unit != "m" && unit != "mm") return fail("unknown unit '" + unit + "' (m or mm)");
        if (t_unit && *t_unit != unit) return fail("unit " + unit + ", but another translation column is in " + *t_unit);
        t_unit = unit;
      }
    } else if ((a = AxisAfter(name, {"q", "q_", "quat_", "qu_", "orientation_", "rot_q"}, "xyzw")) >= 0 ||
               kind == Kind::kQuaternion) {
      if (!unit.empty()) return fail("a quaternion has no unit, got '" + unit + "'");
      ok = set(&l.r[a >= 0 ? a : word_axis]);
      quat = true;
    } else if ((a = AxisAfter(name, {"q"}, "1234")) >= 0) {  // ABB: q1 q2 q3 q4 = w x y z
      if (!unit.empty()) return fail("a quaternion has no unit, got '" + unit + "'");
      ok = set(&l.r[a == 0 ? 3 : a - 1]);
      abb = true;
    } else if ((a = AxisAfter(name, {"r"}, "xyz")) >= 0) {
      if (!unit.empty() && unit != "rad") {
        return fail("unit '" + unit + "': rx,ry,rz are a rotation vector in radians (rad)");
      }
      ok = set(&l.r[a]);
      rotvec = true;
    } else if ((a = AxisAfter(name, {""}, "abc")) >= 0 || (a = AxisAfter(name, {""}, "rpw")) >= 0) {
      // KUKA's A B C, or Fanuc's W (about x), P (about y), R (about z): degrees
      if (!unit.empty() && unit != "deg" && unit != "\xC2\xB0") {
        return fail("unit '" + unit + "': KUKA's A,B,C and Fanuc's W,P,R are angles in degrees (deg)");
      }
      ok = set(&l.r[a]);
      (name == "a" || name == "b" || name == "c" ? kuka : fanuc) = true;
    } else {
      if (!actual_log && !OtherQuantity(words)) unknown.push_back(i);
      continue;
    }
    if (int(quat) + int(abb) + int(rotvec) + int(kuka) + int(fanuc) > std::max(kinds_before, 1)) {
      return fail("more than one kind of rotation columns (a quaternion, q1..q4, rx,ry,rz, a,b,c or w,p,r)");
    }
    if (!ok) return fail("a second column for the same value");
    used += (used.empty() ? "" : ",") + name;
  }
  if (!unknown.empty()) {
    if (!strict) return std::nullopt;
    const size_t i = unknown.front();
    throw InputError(where, "column " + std::to_string(i + 1) + " '" + std::string(TrimBlanks(fields[i])) +
                                "': unknown column name (expected x,y,z with qx,qy,qz,qw, q1..q4, rx,ry,rz, a,b,c or "
                                "w,p,r; time, frame, velocity, bias and covariance columns are skipped; "
                                "docs/pipeline.md)");
  }
  if (l.time >= 0) {
    std::string unit;
    used = NameAndUnit(fields[size_t(l.time)], &unit) + (used.empty() ? "" : ",") + used;
  }
  const int kinds = int(quat) + int(abb) + int(rotvec) + int(kuka) + int(fanuc);
  auto fail_all = [&](const std::string& why) -> std::optional<Layout> {
    if (!strict) return std::nullopt;
    throw InputError(where, "header '" + names + "': " + why);
  };
  if (kinds != 1) return fail_all(kinds == 0 ? "no rotation columns (qx,qy,qz,qw, q1..q4, rx,ry,rz, a,b,c or w,p,r)"
                                             : "more than one kind of rotation columns");
  if (l.t[0] < 0 || l.t[1] < 0 || l.t[2] < 0) return fail_all("needs the translation columns x, y and z");
  const int needed = quat || abb ? 4 : 3;
  for (int k = 0; k < needed; ++k) {
    if (l.r[k] < 0) return fail_all("a rotation column is missing");
  }
  if (rotvec && vicon_columns) {
    return fail_all("Vicon's RX RY RZ (beside its Sub Frame) are angles in degrees, not a rotation vector in radians: "
                    "give the rotation as a quaternion (qx,qy,qz,qw)");
  }
  // Fanuc's W P R are KUKA's C B A: R = Rz(r) Ry(p) Rx(w).
  l.rotation = quat || abb ? Rotation::kQuaternion : rotvec ? Rotation::kRotationVector : Rotation::kKukaAbc;
  const int others = int(fields.size()) - int(std::count(used.begin(), used.end(), ',')) - 1;
  l.form = "CSV columns " + used + (others > 0 ? ", " + std::to_string(others) + " other" + (others > 1 ? "s" : "") + " skipped" : "");
  if (t_unit) *header_units = *t_unit == "mm" ? PoseUnits::kMillimetres : PoseUnits::kMetres;
  return l;
}

Layout HeaderlessLayout(size_t n, char separator, const PoseFileOptions& o, const std::string& where) {
  Layout l;
  l.fields = n;
  auto order_needed = [&](const std::string& what) {
    if (!o.order) {
      throw InputError(where, std::to_string(n) + " numbers per row (" + what +
                                  "), no header: is the quaternion's w first or last? Give --pose-order xyzw or "
                                  "wxyz, or a header line naming the columns (x,y,z,qx,qy,qz,qw)");
    }
  };
  auto quaternion = [&](int first, QuaternionOrder order) {
    for (int k = 0; k < 3; ++k) l.t[k] = first + k;
    for (int k = 0; k < 4; ++k) l.r[k] = order == QuaternionOrder::kXyzw ? first + 3 + k : first + 3 + (k + 1) % 4;
    l.form = std::string(first ? "t," : "") + "x,y,z," + (order == QuaternionOrder::kXyzw ? "qx,qy,qz,qw" : "qw,qx,qy,qz");
  };
  if (n == 7) {
    order_needed("x y z and a quaternion");
    quaternion(0, *o.order);
    l.form = "rows " + l.form;
  } else if (n == 8 && separator == ' ') {
    quaternion(1, o.order.value_or(QuaternionOrder::kXyzw));
    l.time = 0;  // TUM's timestamp, seconds
    l.form = o.order.value_or(QuaternionOrder::kXyzw) == QuaternionOrder::kXyzw ? "TUM (timestamp tx ty tz qx qy qz qw)"
                                                                                : "rows " + l.form;
  } else if (n == 8) {
    order_needed("a time or index, x y z and a quaternion");
    quaternion(1, *o.order);
    l.form = "rows " + l.form;
  } else if (n == 12 || n == 16) {
    l.rotation = n == 12 ? Rotation::kMatrix3x4 : Rotation::kMatrix4x4;
    l.form = n == 12 ? "3x4 matrices (row-major)" : "4x4 matrices (row-major)";
  } else if (n == 6) {
    throw InputError(where, "6 numbers per row, no header: x y z and which three angles? Give a header line: "
                            "x,y,z,rx,ry,rz (a rotation vector in radians, Universal Robots) or x,y,z,a,b,c (KUKA's "
                            "angles in degrees)");
  } else {
    throw InputError(where, std::to_string(n) + " numbers per row: expected 7 (x y z + quaternion), 8 (TUM: timestamp "
                                                "tx ty tz qx qy qz qw), 12 (3x4 matrix) or 16 (4x4 matrix), or a "
                                                "header line naming the columns");
  }
  return l;
}

}  // namespace lt::pose_file_detail

// The layout of a pose file's columns (pose_file_layout.h): column names with their
// units, the header's layout, and the layout of rows without a header. Reading the rows
// into poses is in pose_file.cpp.
#include "pipeline/pose_file_layout.h"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/pose_file_names.h"

namespace lt::pose_file_detail {

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
  // ROS: a stamp in two columns (3 in the header, 2 else), the message's header.stamp (2), before another
  // time (1), before rosbag's %time (0).
  int time_rank = -1;
  // A Universal Robots RTDE log or a KUKA RSI log: their other fields (joints, speeds,
  // the commanded pose, process signals) are skipped.
  // An RTDE log's pose is its actual_TCP_pose, else (a planned path) its target_TCP_pose.
  // Vicon's columns hold a "Sub Frame".
  // A Franka robot's log (its O_T_EE): every other field is skipped.
  bool actual_log = false, rtde_actual = false, vicon_columns = false, franka = false, franka_measured = false;
  std::vector<size_t> unknown;
  std::vector<size_t> quaternion_angles;  // PlotJuggler's roll_deg.. beside the quaternion it derives them from
  size_t franka_first = 0;
  for (size_t i = 0; i < fields.size(); ++i) {
    std::string unit;
    const std::string name = NameAndUnit(fields[i], &unit);
    rtde_actual |= name.rfind("actual_tcp_pose_", 0) == 0;
    actual_log |= name.rfind("target_tcp_pose_", 0) == 0 || RsiActual(Words(name)) >= 0;
    vicon_columns |= name == "sub frame";
    bool commanded = false;
    if (FrankaPoseElement(Lower(fields[i]), &commanded) >= 0) {
      if (!franka) franka_first = i;
      franka = true, franka_measured |= !commanded;
    }
  }
  actual_log |= rtde_actual || franka;
  // A time in two columns (ROS's stamp.sec, stamp.nanosec), by the name before its parts.
  struct TwoColumnTime {
    std::string prefix;
    int sec = -1, nanosec = -1;
  };
  std::vector<TwoColumnTime> two_column_times;
  int matrix_elements = 0;
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
    bool commanded = false;
    if (const int k = FrankaPoseElement(Lower(fields[i]), &commanded); k >= 0) {
      // Column-major: element k is row k % 4, column k / 4. Its desired and commanded poses are skipped.
      if (commanded == franka_measured) continue;
      if (!set(&l.m[4 * (k % 4) + k / 4])) return fail("a second column for the same value");
      ++matrix_elements;
      if (!used.empty()) used += ',';
      used += Lower(TrimBlanks(fields[i]));
      continue;
    }
    const std::vector<std::string> words = Words(name);
    if (ChildFrame(words)) {
      // ROS's child_frame_id (a tf or Odometry message): the body whose pose the row is.
      if (!set(&l.body)) return fail("a second child frame column");
      l.body_column = std::string(TrimBlanks(fields[i]));
      continue;
    }
    double part = 0;
    std::string prefix;
    if (TimePart(words, &part, &prefix)) {
      auto it = std::find_if(two_column_times.begin(), two_column_times.end(),
                             [&](const TwoColumnTime& t) { return t.prefix == prefix; });
      if (it == two_column_times.end()) it = two_column_times.insert(it, TwoColumnTime{prefix});
      if (!set(part == 1.0 ? &it->sec : &it->nanosec)) return fail("a second column for the same value");
      continue;
    }
    bool known = false;
    double to_s = TimeColumn(name, unit, &known);
    int rank = 1;
    if (to_s == 0 && name == "%time") {  // rostopic echo -p: when rosbag recorded the message, ns
      to_s = 1e-9, known = true, rank = 0;
    } else if (to_s == 0 && name == "__time") {  // PlotJuggler's CSV export: seconds
      to_s = 1.0, known = true;
    } else if (to_s == 0 && words.size() >= 2 && words.back() == "stamp" && words[words.size() - 2] == "header") {
      // ROS's header.stamp: rostopic echo -p's field.header.stamp in ns; a topic path's /topic/header/stamp
      // in s as PlotJuggler writes it, or in ns as other bag-to-CSV tools do: by its size (ns from 1e17).
      const bool path = name.find('/') != std::string::npos;
      to_s = path ? 1.0 : 1e-9, known = !path, rank = 2;
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
      if (QuaternionAngles(words)) {
        quaternion_angles.push_back(i);
      } else if (!actual_log && !OtherQuantity(words)) {
        unknown.push_back(i);
      }
      continue;
    }
    if (int(quat) + int(abb) + int(rotvec) + int(kuka) + int(fanuc) > std::max(kinds_before, 1)) {
      return fail("more than one kind of rotation columns (a quaternion, q1..q4, rx,ry,rz, a,b,c or w,p,r)");
    }
    if (!ok) return fail("a second column for the same value");
    used += (used.empty() ? "" : ",") + name;
  }
  if (!quat) unknown.insert(unknown.end(), quaternion_angles.begin(), quaternion_angles.end());  // the only rotation
  std::sort(unknown.begin(), unknown.end());
  if (!unknown.empty()) {
    if (!strict) return std::nullopt;
    const size_t i = unknown.front();
    throw InputError(where, "column " + std::to_string(i + 1) + " '" + std::string(TrimBlanks(fields[i])) +
                                "': unknown column name (expected x,y,z with qx,qy,qz,qw, q1..q4, rx,ry,rz, a,b,c or "
                                "w,p,r; time, frame, velocity, bias and covariance columns are skipped; "
                                "docs/pipeline.md)");
  }
  auto fail_all = [&](const std::string& why) -> std::optional<Layout> {
    if (!strict) return std::nullopt;
    throw InputError(where, "header '" + names + "': " + why);
  };
  for (const TwoColumnTime& t : two_column_times) {
    const std::vector<std::string> words = Words(t.prefix);
    const bool stamp = words.empty() || words.back() == "stamp";  // a ROS stamp's parts: both needed
    if ((t.sec < 0 || t.nanosec < 0) && stamp) {
      return fail_all("a time's " + std::string(t.sec < 0 ? "nanoseconds" : "seconds") + " without its " +
                      (t.sec < 0 ? "seconds" : "nanoseconds") + " column (" + (t.prefix.empty() ? "secs" : t.prefix) +
                      ": sec and nanosec, or secs and nsecs)");
    }
    // A message's stamp (3 in its header, else 2) before a single time column ("time_sec",
    // "timestamp_nsec" alone: 1), before rosbag's %time.
    const int rank = t.sec < 0 || t.nanosec < 0                                   ? 1
                     : std::find(words.begin(), words.end(), "header") != words.end() ? 3
                                                                                    : 2;
    if (rank == time_rank) return fail_all("a second time column (" + (t.prefix.empty() ? "secs" : t.prefix) + ")");
    if (rank > time_rank) {
      time_rank = rank;
      l.time = t.sec >= 0 ? t.sec : t.nanosec, l.time_nanosec = t.sec >= 0 ? t.nanosec : -1;
      l.time_to_s = t.sec >= 0 ? 1.0 : 1e-9, l.time_unit_known = true;
    }
  }
  if (l.time >= 0) {
    std::string unit;
    std::string time = NameAndUnit(fields[size_t(l.time)], &unit);
    if (l.time_nanosec >= 0) time += ',' + NameAndUnit(fields[size_t(l.time_nanosec)], &unit);
    used = time + (used.empty() ? "" : ",") + used;
  }
  if (franka) {
    if (!franka_measured) {
      if (!strict) return std::nullopt;
      throw InputError(where, "column " + std::to_string(franka_first + 1) + " '" +
                                  std::string(TrimBlanks(fields[franka_first])) +
                                  "': a Franka log of the commanded pose only (libfranka's cmd.O_T_EE_d: the identity "
                                  "unless the motion was commanded as Cartesian poses, and not where the robot was): "
                                  "log the robot state's O_T_EE");
    }
    if (matrix_elements != 16) return fail_all("Franka's O_T_EE needs its 16 elements, got " + std::to_string(matrix_elements));
    l.rotation = Rotation::kMatrixColumns;
    const int others = int(fields.size()) - int(std::count(used.begin(), used.end(), ',')) - 1;
    l.form = "CSV columns " + used + " (Franka O_T_EE, column-major)" +
             (others > 0 ? ", " + std::to_string(others) + " others skipped" : "");
    *header_units = PoseUnits::kMetres;
    return l;
  }
  const int kinds = int(quat) + int(abb) + int(rotvec) + int(kuka) + int(fanuc);
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

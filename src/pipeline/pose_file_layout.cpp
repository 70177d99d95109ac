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
// another name, -1 for an unknown unit.
double TimeColumn(const std::string& name, const std::string& unit) {
  for (const char* s : {"t", "time", "timestamp", "stamp"}) {
    if (name != s) continue;
    if (unit.empty() || unit == "s") return 1.0;
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
  for (const char* s : {"frame", "index", "image", "file", "filename", "id"}) {
    if (name == s) return true;
  }
  return false;
}

}  // namespace

// The layout a header names; nullopt when `strict` is false and a name is not known.
std::optional<Layout> HeaderLayout(const std::vector<std::string_view>& fields, const std::string& where, bool strict,
                                   std::optional<PoseUnits>* header_units) {
  Layout l;
  l.fields = fields.size();
  bool quat = false, abb = false, rotvec = false, kuka = false, fanuc = false;
  std::optional<std::string> t_unit;
  std::string names;
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
    bool ok = true;
    if (Skipped(name)) continue;
    if (const double to_s = TimeColumn(name, unit); to_s != 0) {
      if (to_s < 0) return fail("unknown time unit '" + unit + "' (s, ms, us or ns)");
      if (l.time >= 0) return fail("a second time column");
      l.time = c;
      l.time_to_s = to_s;
      continue;
    }
    const int kinds_before = int(quat) + int(abb) + int(rotvec) + int(kuka) + int(fanuc);
    if (name.rfind("actual_tcp_pose_", 0) == 0 && name.size() == 17 && name[16] >= '0' && name[16] <= '5') {
      // Universal Robots' RTDE log: x y z in metres, then the rotation vector.
      const int k = name[16] - '0';
      ok = k < 3 ? set(&l.t[k]) : set(&l.r[k - 3]);
      rotvec |= k >= 3;
      if (k < 3 && !t_unit) t_unit = "m";
    } else if ((a = AxisAfter(name, {"", "t", "t_", "p_", "pos_", "position_", "trans_", "translation_", "tcp_"}, "xyz")) >= 0) {
      ok = set(&l.t[a]);
      if (!unit.empty()) {
        if (unit != "m" && unit != "mm") return fail("unknown unit '" + unit + "' (m or mm)");
        if (t_unit && *t_unit != unit) return fail("unit " + unit + ", but another translation column is in " + *t_unit);
        t_unit = unit;
      }
    } else if ((a = AxisAfter(name, {"q", "q_", "quat_", "qu_", "orientation_", "rot_q"}, "xyzw")) >= 0) {
      ok = set(&l.r[a]);
      quat = true;
    } else if ((a = AxisAfter(name, {"q"}, "1234")) >= 0) {  // ABB: q1 q2 q3 q4 = w x y z
      ok = set(&l.r[a == 0 ? 3 : a - 1]);
      abb = true;
    } else if ((a = AxisAfter(name, {"r"}, "xyz")) >= 0) {
      ok = set(&l.r[a]);
      rotvec = true;
    } else if ((a = AxisAfter(name, {""}, "abc")) >= 0) {
      ok = set(&l.r[a]);
      kuka = true;
    } else if ((a = AxisAfter(name, {""}, "rpw")) >= 0) {  // Fanuc: W about x, P about y, R about z
      ok = set(&l.r[a]);
      fanuc = true;
    } else {
      return fail("unknown column name (expected x,y,z with qx,qy,qz,qw, q1..q4, rx,ry,rz, a,b,c or w,p,r; time and "
                  "frame columns are skipped; docs/pipeline.md)");
    }
    if (int(quat) + int(abb) + int(rotvec) + int(kuka) + int(fanuc) > std::max(kinds_before, 1)) {
      return fail("more than one kind of rotation columns (a quaternion, q1..q4, rx,ry,rz, a,b,c or w,p,r)");
    }
    if (!ok) return fail("a second column for the same value");
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
  // Fanuc's W P R are KUKA's C B A: R = Rz(r) Ry(p) Rx(w).
  l.rotation = quat || abb ? Rotation::kQuaternion : rotvec ? Rotation::kRotationVector : Rotation::kKukaAbc;
  l.form = "CSV columns " + names;
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

#include "pipeline/pose_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string_view>

#include "core/error.h"
#include "core/text_fields.h"

namespace lt {

namespace {

constexpr double kQuaternionTolerance = 1e-3;
constexpr double kMatrixTolerance = 1e-4;
constexpr double kMillimetreHint_m = 5.0;  // a translation beyond this, read as metres, is probably in mm
constexpr double kDegToRad = M_PI / 180.0;

// What a rotation's columns hold.
enum class Rotation { kQuaternion, kRotationVector, kKukaAbc, kMatrix3x4, kMatrix4x4 };

// Where each value of a row is: columns of x y z, and of the rotation's values
// (quaternion: x y z w; rotation vector: x y z; KUKA: a b c).
struct Layout {
  Rotation rotation = Rotation::kQuaternion;
  size_t fields = 0;
  int t[3] = {-1, -1, -1};
  int time = -1;            // the column of the time, -1: none
  double time_to_s = 1.0;   // its unit
  int r[4] = {-1, -1, -1, -1};
  std::string form;
};

std::string Lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

// Fields separated by ';' (spreadsheets with a decimal comma), tab, ',' or
// blanks, without the double quotes spreadsheets put around them.
std::vector<std::string_view> SplitRow(std::string_view line, char* separator) {
  std::vector<std::string_view> fields;
  *separator = ' ';
  for (char c : {';', '\t', ','}) {
    if (line.find(c) != std::string_view::npos) {
      *separator = c;
      break;
    }
  }
  fields = *separator == ' ' ? SplitBlanks(line) : SplitFields(line, *separator);
  for (std::string_view& f : fields) {
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = TrimBlanks(f.substr(1, f.size() - 2));
  }
  return fields;
}

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

bool AllNumbers(const std::vector<std::string_view>& fields) {
  return std::all_of(fields.begin(), fields.end(), [](std::string_view f) { return ParseFiniteNumber(f).has_value(); });
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

Pose RowPose(const Layout& l, const std::vector<double>& v, double scale, const std::string& where) {
  Pose pose = Pose::Identity();
  if (l.rotation == Rotation::kMatrix3x4 || l.rotation == Rotation::kMatrix4x4) {
    Eigen::Matrix3d R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R(i, j) = v[size_t(4 * i + j)];
    pose.translation() = Eigen::Vector3d(v[3], v[7], v[11]) * scale;
    if (l.rotation == Rotation::kMatrix4x4 &&
        !(v[12] == 0 && v[13] == 0 && v[14] == 0 && v[15] == 1)) {
      throw InputError(where, "the last row of a 4x4 pose must be 0 0 0 1, got " + FormatNumber(v[12]) + " " +
                                  FormatNumber(v[13]) + " " + FormatNumber(v[14]) + " " + FormatNumber(v[15]));
    }
    const double ortho = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    const double det = R.determinant();
    if (ortho > kMatrixTolerance || std::abs(det - 1.0) > kMatrixTolerance) {
      throw InputError(where, "not a rotation matrix (orthonormal, determinant +1, to 1e-4): R*R^T deviates by " +
                                  FormatNumber(ortho) + ", determinant " + FormatNumber(det));
    }
    pose.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
    return pose;
  }
  pose.translation() = Eigen::Vector3d(v[size_t(l.t[0])], v[size_t(l.t[1])], v[size_t(l.t[2])]) * scale;
  if (l.rotation == Rotation::kQuaternion) {
    Eigen::Quaterniond q(v[size_t(l.r[3])], v[size_t(l.r[0])], v[size_t(l.r[1])], v[size_t(l.r[2])]);
    if (std::abs(q.norm() - 1.0) > kQuaternionTolerance) {
      throw InputError(where, "the quaternion must have unit norm (to 1e-3), got norm " + FormatNumber(q.norm()));
    }
    pose.linear() = q.normalized().toRotationMatrix();
  } else if (l.rotation == Rotation::kRotationVector) {
    const Eigen::Vector3d r(v[size_t(l.r[0])], v[size_t(l.r[1])], v[size_t(l.r[2])]);
    const double angle = r.norm();
    if (angle > 0) pose.linear() = Eigen::AngleAxisd(angle, r / angle).toRotationMatrix();
  } else {
    const double a = v[size_t(l.r[0])] * kDegToRad, b = v[size_t(l.r[1])] * kDegToRad, c = v[size_t(l.r[2])] * kDegToRad;
    pose.linear() = (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
  }
  return pose;
}

}  // namespace

QuaternionOrder ParseQuaternionOrder(const std::string& text, const std::string& option) {
  const std::string s = Lower(text);
  if (s == "xyzw") return QuaternionOrder::kXyzw;
  if (s == "wxyz") return QuaternionOrder::kWxyz;
  throw InputError(option, "unknown quaternion order '" + text + "' (expected xyzw or wxyz)");
}

PoseUnits ParsePoseUnits(const std::string& text, const std::string& option) {
  const std::string s = Lower(text);
  if (s == "m") return PoseUnits::kMetres;
  if (s == "mm") return PoseUnits::kMillimetres;
  throw InputError(option, "unknown units '" + text + "' (expected m or mm)");
}

PoseFile ParsePoseFile(const std::string& text, const std::string& name, const PoseFileOptions& options,
                       const std::function<void(const std::string&)>& warn) {
  PoseFile out;
  std::optional<Layout> layout;
  std::optional<PoseUnits> header_units;
  std::string last_comment;  // "# x y z qx qy qz qw" right above the first row may name the columns
  int last_comment_line = 0;
  size_t line_no = 0;
  size_t pos = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  double largest_m = 0;
  int largest_line = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string_view line = TrimBlanks(std::string_view(text).substr(pos, end - pos));
    pos = end + 1;
    ++line_no;
    if (line.empty()) continue;
    if (line.front() == '#') {
      last_comment = std::string(line.substr(1));
      last_comment_line = int(line_no);
      continue;
    }
    const std::string where = name + ":" + std::to_string(line_no);
    char separator = ' ';
    const std::vector<std::string_view> fields = SplitRow(line, &separator);
    if (!layout) {
      if (!AllNumbers(fields)) {
        layout = HeaderLayout(fields, where, true, &header_units);
        continue;
      }
      if (last_comment_line == int(line_no) - 1) {
        char comment_separator = ' ';
        const std::vector<std::string_view> names = SplitRow(last_comment, &comment_separator);
        if (names.size() == fields.size() && !AllNumbers(names)) {
          layout = HeaderLayout(names, name + ":" + std::to_string(last_comment_line), false, &header_units);
        }
      }
      if (!layout) layout = HeaderlessLayout(fields.size(), separator, options, where);
    }
    if (out.poses.empty()) {
      if (header_units && options.units && *header_units != *options.units) {
        throw InputError(name, std::string("the header gives translations in ") +
                                   (*header_units == PoseUnits::kMillimetres ? "mm" : "m") + ", the option in " +
                                   (*options.units == PoseUnits::kMillimetres ? "mm" : "m"));
      }
      out.units = options.units.value_or(header_units.value_or(PoseUnits::kMetres));
    }
    if (fields.size() != layout->fields) {
      throw InputError(where, std::to_string(fields.size()) + " fields, but the first row has " +
                                  std::to_string(layout->fields) + " (" + layout->form + ")");
    }
    std::vector<double> v(fields.size(), 0.0);
    for (size_t i = 0; i < fields.size(); ++i) {
      const auto number = ParseFiniteNumber(fields[i]);
      if (!number) {
        // Skipped columns (time, image name) may hold anything.
        bool used = layout->rotation == Rotation::kMatrix3x4 || layout->rotation == Rotation::kMatrix4x4;
        for (int k : layout->t) used |= k == int(i);
        for (int k : layout->r) used |= k == int(i);
        if (!used) continue;
        const bool decimal_comma = fields[i].find(',') != std::string_view::npos;
        throw InputError(where, "field " + std::to_string(i + 1) + " is not a finite number: \"" +
                                    std::string(fields[i]) + "\"" +
                                    (decimal_comma ? " (a decimal comma? numbers need a decimal point)" : ""));
      }
      v[i] = *number;
    }
    const double scale = out.units == PoseUnits::kMillimetres ? 1e-3 : 1.0;
    out.poses.push_back(RowPose(*layout, v, scale, where));
    out.lines.push_back(int(line_no));
    if (layout->time >= 0 && out.times_s.size() + 1 == out.poses.size()) {
      // A time that is no number (a date) leaves the file without times: poses go by row.
      const auto t = ParseFiniteNumber(fields[size_t(layout->time)]);
      if (t) {
        out.times_s.push_back(*t * layout->time_to_s);
      } else {
        out.times_s.clear();
        layout->time = -1;
      }
    }
    const double t = out.poses.back().translation().norm();
    if (t > largest_m) largest_m = t, largest_line = int(line_no);
  }
  if (out.poses.empty()) throw InputError(name, "holds no pose (one row per frame expected)");
  out.form = layout->form;
  if (!options.units && !header_units && largest_m > kMillimetreHint_m && warn) {
    warn(name + ":" + std::to_string(largest_line) + ": a translation of " + FormatNumber(largest_m) +
         " m: are the poses in millimetres (as KUKA, ABB and Fanuc controllers write them)? --pose-units mm reads "
         "them so");
  }
  return out;
}

PoseFile ReadPoseFile(const std::filesystem::path& path, const PoseFileOptions& options,
                      const std::function<void(const std::string&)>& warn) {
  if (std::filesystem::is_directory(path)) throw InputError(path.string(), "is a folder, not a pose file");
  if (!std::filesystem::exists(path)) throw InputError(path.string(), "no such file");
  return ParsePoseFile(ReadTextFile(path, path.string()), path.string(), options, warn);
}

}  // namespace lt

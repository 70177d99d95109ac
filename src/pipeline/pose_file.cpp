// Reading a pose file (pose_file.h): its rows, each as a pose, with units, times and
// the checks of each rotation. The layout of the columns (header names, headerless
// forms) is in pose_file_layout.cpp.
#include "pipeline/pose_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string_view>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/pose_file_layout.h"
#include "pipeline/pose_file_motive.h"

namespace lt {

using namespace pose_file_detail;

namespace {

constexpr double kQuaternionTolerance = 1e-3;
constexpr double kMatrixTolerance = 1e-4;
constexpr double kMillimetreHint_m = 5.0;  // a translation beyond this, read as metres, is probably in mm
constexpr double kDegToRad = M_PI / 180.0;
// A time without a unit this large is no time in seconds (3e9 years): nanoseconds.
constexpr double kNanosecondTimes = 1e17;

// Fields separated by ';' (spreadsheets with a decimal comma), tab, ',' or blanks,
// without the double quotes spreadsheets put around them. A separator inside double
// quotes or brackets separates nothing: PlotJuggler names a covariance's elements
// "/odom/pose/covariance[0;1]", other writers "cov[4,4]", quoted or not.
std::vector<std::string_view> SplitRow(std::string_view line, char* separator) {
  // Calls f(i) for each character outside quotes and brackets.
  auto outside = [&](auto f) {
    bool quoted = false;
    int depth = 0;
    for (size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (c == '"') quoted = !quoted;
      if (quoted) continue;
      if (c == '[') ++depth;
      if (c == ']' && depth > 0) --depth;
      if (depth == 0 && !f(i)) return;
    }
  };
  *separator = ' ';
  for (char s : {';', '\t', ','}) {
    outside([&](size_t i) { return line[i] == s ? (*separator = s, false) : true; });
    if (*separator != ' ') break;
  }
  if (*separator == ' ') return SplitBlanks(line);
  std::vector<std::string_view> fields;
  size_t begin = 0;
  outside([&](size_t i) {
    if (line[i] == *separator) fields.push_back(TrimBlanks(line.substr(begin, i - begin))), begin = i + 1;
    return true;
  });
  fields.push_back(TrimBlanks(line.substr(begin)));
  for (std::string_view& f : fields) {
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = TrimBlanks(f.substr(1, f.size() - 2));
  }
  return fields;
}

bool IsMatrix(Rotation r) {
  return r == Rotation::kMatrix3x4 || r == Rotation::kMatrix4x4 || r == Rotation::kMatrixColumns;
}

bool AllNumbers(const std::vector<std::string_view>& fields) {
  return std::all_of(fields.begin(), fields.end(), [](std::string_view f) { return ParseFiniteNumber(f).has_value(); });
}

Pose RowPose(const Layout& l, const std::vector<double>& v, double scale, const std::string& where) {
  Pose pose = Pose::Identity();
  if (IsMatrix(l.rotation)) {
    // The matrix's row-major elements: the row's first 12 or 16 numbers, or the named columns.
    auto e = [&](int k) { return v[size_t(l.rotation == Rotation::kMatrixColumns ? l.m[k] : k)]; };
    Eigen::Matrix3d R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R(i, j) = e(4 * i + j);
    pose.translation() = Eigen::Vector3d(e(3), e(7), e(11)) * scale;
    if (l.rotation != Rotation::kMatrix3x4 && !(e(12) == 0 && e(13) == 0 && e(14) == 0 && e(15) == 1)) {
      throw InputError(where, "the last row of a 4x4 pose must be 0 0 0 1, got " + FormatNumber(e(12)) + " " +
                                  FormatNumber(e(13)) + " " + FormatNumber(e(14)) + " " + FormatNumber(e(15)) +
                                  (l.rotation == Rotation::kMatrixColumns ? " (its elements are read column-major)" : ""));
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
    if (angle > 2 * M_PI + 1e-9) {  // a rotation vector's angle is at most pi (2 pi at most from any writer)
      throw InputError(where, "a rotation vector of " + FormatNumber(angle) +
                                  " rad (more than 2 pi): angles in degrees? rx,ry,rz are a rotation vector in radians");
    }
    if (angle > 0) pose.linear() = Eigen::AngleAxisd(angle, r / angle).toRotationMatrix();
  } else {
    const double a = v[size_t(l.r[0])] * kDegToRad, b = v[size_t(l.r[1])] * kDegToRad, c = v[size_t(l.r[2])] * kDegToRad;
    pose.linear() = (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
  }
  return pose;
}

// The body of the rows read: --pose-body's, else the file's one. Throws lt::InputError
// for a file of several without --pose-body, a --pose-body the file does not hold, or
// one given for a file that names no bodies.
void CheckBodies(const std::string& name, const PoseFileOptions& options, bool motive,
                 const std::optional<Layout>& layout, int layout_line,
                 const std::vector<std::pair<std::string, int>>& bodies) {
  if (motive) return;  // MotiveAsOneHeader chose its rigid body
  if (!layout || layout->body < 0) {
    if (options.body) {
      throw InputError(name, "--pose-body '" + *options.body + "': the file names no bodies (--pose-body picks an "
                             "OptiTrack Motive export's rigid body, or the rows of one child_frame_id)");
    }
    return;
  }
  std::vector<std::string> names;
  for (const auto& b : bodies) names.push_back(b.first);
  const std::string listed = ListFirst(names, kBodiesListed, '\'');
  const std::string column = "column " + std::to_string(layout->body + 1) + " '" + layout->body_column + "'";
  if (options.body && std::none_of(bodies.begin(), bodies.end(), [&](const auto& b) { return b.first == *options.body; })) {
    throw InputError(name + ":" + std::to_string(layout_line), "no rows of the child frame '" + *options.body + "' (" +
                                                                   column + "): its rows are of " + listed);
  }
  if (!options.body && bodies.size() > 1) {
    throw InputError(name + ":" + std::to_string(bodies[1].second),
                     "rows of several child frames (" + column + "), mixed in one trajectory if read: give --pose-body: " +
                         listed);
  }
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

PoseFile ParsePoseFile(const std::string& file_text, const std::string& name, const PoseFileOptions& options,
                       const std::function<void(const std::string&)>& warn) {
  // An OptiTrack Motive export: its rows above the data read as one header line.
  const std::optional<MotiveText> motive = MotiveAsOneHeader(file_text, name, options.body);
  const std::string& text = motive ? motive->text : file_text;
  PoseFile out;
  std::optional<Layout> layout;
  std::optional<PoseUnits> header_units;
  std::string last_comment;  // "# x y z qx qy qz qw" right above the first row may name the columns
  int last_comment_line = 0;
  int layout_line = 0;
  // Rows naming their body (a child_frame_id column): the bodies in file order, with the line of each one's first row.
  std::vector<std::pair<std::string, int>> bodies;
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
      if (line.find("Image list with two lines of data per image") != std::string_view::npos) {
        throw InputError(name + ":" + std::to_string(line_no),
                         "COLMAP's images.txt is not read as poses: its QW QX QY QZ TX TY TZ are camera_from_world (the "
                         "inverse of world_from_cam), in the reconstruction's own scale (not metres unless scaled), two "
                         "lines per image, in image id order: write world_from_cam in metres per frame, in frame order, "
                         "e.g. x,y,z,qx,qy,qz,qw");
      }
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
        layout_line = int(line_no);
        continue;
      }
      if (last_comment_line == int(line_no) - 1) {
        char comment_separator = ' ';
        const std::vector<std::string_view> names = SplitRow(last_comment, &comment_separator);
        if (names.size() == fields.size() && !AllNumbers(names)) {
          layout = HeaderLayout(names, name + ":" + std::to_string(last_comment_line), false, &header_units);
          layout_line = last_comment_line;
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
    if (layout->body >= 0) {
      // Rows of several bodies (a tf topic's frames): the chosen one's only.
      const std::string body(fields[size_t(layout->body)]);
      if (std::none_of(bodies.begin(), bodies.end(), [&](const auto& b) { return b.first == body; })) {
        bodies.emplace_back(body, int(line_no));
      }
      if (body != (options.body ? *options.body : bodies.front().first)) continue;
    }
    std::vector<double> v(fields.size(), 0.0);
    for (size_t i = 0; i < fields.size(); ++i) {
      const auto number = ParseFiniteNumber(fields[i]);
      if (!number) {
        // Skipped columns (time, image name) may hold anything.
        bool used = IsMatrix(layout->rotation) && layout->rotation != Rotation::kMatrixColumns;
        for (int k : layout->t) used |= k == int(i);
        for (int k : layout->r) used |= k == int(i);
        for (int k : layout->m) used |= k == int(i);
        if (!used) continue;
        const bool decimal_comma = fields[i].find(',') != std::string_view::npos;
        if (fields[i].empty()) {
          throw InputError(where, "field " + std::to_string(i + 1) +
                                      " is empty (a frame the tracker lost, or a row of another topic in a log of several, "
                                      "as PlotJuggler exports? give only rows holding the pose)");
        }
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
      auto t = ParseFiniteNumber(fields[size_t(layout->time)]);
      if (t && layout->time_nanosec >= 0) {
        // ROS's stamp in two columns: sec + nanosec * 1e-9 (a double holds 1.7e9 s to 0.24 us).
        const auto ns = ParseFiniteNumber(fields[size_t(layout->time_nanosec)]);
        t = ns ? std::optional<double>(*t + *ns * 1e-9) : std::nullopt;
      }
      if (t && out.times_s.empty() && !layout->time_unit_known && std::abs(*t) >= kNanosecondTimes) {
        layout->time_to_s = 1e-9;  // seconds since 1970 are ~1.7e9, nanoseconds ~1.7e18 (EuRoC's #timestamp)
        layout->form += ", times in ns";
      }
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
  CheckBodies(name, options, motive.has_value(), layout, layout_line, bodies);
  if (out.poses.empty()) throw InputError(name, "holds no pose (one row per frame expected)");
  out.form = motive ? "OptiTrack Motive rigid body '" + motive->body + "', " + layout->form : layout->form;
  if (layout->body >= 0) out.form += ", child frame '" + (options.body ? *options.body : bodies.front().first) + "'";
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

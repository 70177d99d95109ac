#include "scene/pose_list.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "core/error.h"
#include "core/text_fields.h"

namespace lt {

namespace {

constexpr double kQuaternionTolerance = 1e-3;
constexpr std::string_view kCsvHeader[] = {"t_s", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"};

std::string Where(const std::string& name, size_t line) { return name + ":" + std::to_string(line); }

bool UnitQuaternion(const Eigen::Quaterniond& q) { return std::abs(q.norm() - 1.0) <= kQuaternionTolerance; }

bool EightNumbers(const std::vector<std::string_view>& fields) {
  return fields.size() == 8 &&
         std::all_of(fields.begin(), fields.end(), [](std::string_view f) { return ParseFiniteNumber(f).has_value(); });
}

// A line the format cannot read that is a line of the other format (a TUM file read
// as the default CSV, a CSV file given "format": "tum"), or CSV poses before the
// header: what to change, after the error.
std::string OtherFormatHint(std::string_view line, PoseFileFormat format) {
  if (format == PoseFileFormat::kCsv) {
    if (EightNumbers(SplitBlanks(line))) {
      return " (8 numbers separated by blanks: a TUM trajectory? give the motion \"format\": \"tum\")";
    }
    if (EightNumbers(SplitFields(line, ','))) return " (a pose before the header: the header comes first)";
  } else if (SplitFields(line, ',').size() == 8) {
    return " (fields separated by commas: a CSV pose list? leave out the motion's \"format\": \"tum\")";
  }
  return "";
}

}  // namespace

PoseTrajectory ParsePoseList(const std::string& text, PoseFileFormat format, const std::string& display_name) {
  std::vector<PoseSample> samples;
  bool header_seen = false;
  size_t line_no = 0;
  // A UTF-8 byte order mark (Excel's "CSV UTF-8", Windows editors) is not part of the first line.
  size_t pos = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line = TrimBlanks(std::string_view(text).substr(pos, end - pos));
    pos = end + 1;
    ++line_no;
    if (line.empty() || line.front() == '#') continue;
    const std::string where = Where(display_name, line_no);
    std::vector<std::string_view> fields =
        format == PoseFileFormat::kCsv ? SplitFields(line, ',') : SplitBlanks(line);
    if (format == PoseFileFormat::kCsv && !header_seen) {
      bool ok = fields.size() == 8;
      for (size_t i = 0; ok && i < 8; ++i) ok = fields[i] == kCsvHeader[i];
      if (!ok) {
        throw InputError(where, "expected the header \"t_s,x_m,y_m,z_m,qw,qx,qy,qz\", got \"" + std::string(line) +
                                    "\"" + OtherFormatHint(line, format));
      }
      header_seen = true;
      continue;
    }
    if (fields.size() != 8) {
      throw InputError(where, "expected 8 fields (" +
                                  std::string(format == PoseFileFormat::kCsv ? "t_s,x_m,y_m,z_m,qw,qx,qy,qz"
                                                                             : "timestamp tx ty tz qx qy qz qw") +
                                  "), got " + std::to_string(fields.size()) +
                                  (format == PoseFileFormat::kTum ? OtherFormatHint(line, format) : ""));
    }
    double v[8];
    for (size_t i = 0; i < 8; ++i) {
      auto number = ParseFiniteNumber(fields[i]);
      if (!number) {
        throw InputError(where, "field " + std::to_string(i + 1) + " is not a finite number: \"" +
                                    std::string(fields[i]) + "\"");
      }
      v[i] = *number;
    }
    PoseSample s;
    s.t_s = v[0];
    s.position = Eigen::Vector3d(v[1], v[2], v[3]);
    s.rotation = format == PoseFileFormat::kCsv ? Eigen::Quaterniond(v[4], v[5], v[6], v[7])
                                                : Eigen::Quaterniond(v[7], v[4], v[5], v[6]);
    double norm = s.rotation.norm();
    if (!UnitQuaternion(s.rotation)) {
      throw InputError(where, "quaternion must have unit norm (to 1e-3), got norm " + FormatNumber(norm));
    }
    s.rotation.normalize();
    if (!samples.empty() && !(s.t_s > samples.back().t_s)) {
      throw InputError(where, "time " + FormatNumber(s.t_s) + " does not increase (previous pose at " +
                                  FormatNumber(samples.back().t_s) + ")");
    }
    samples.push_back(s);
  }
  if (format == PoseFileFormat::kCsv && !header_seen) {
    throw InputError(display_name, "empty pose list: expected the header \"t_s,x_m,y_m,z_m,qw,qx,qy,qz\"");
  }
  if (samples.size() < 2) {
    throw InputError(display_name, "a pose list needs at least two poses, got " + std::to_string(samples.size()));
  }
  return PoseTrajectory(std::move(samples));
}

PoseTrajectory ReadPoseList(const std::filesystem::path& path, PoseFileFormat format, const std::string& display_name) {
  std::string name = display_name.empty() ? path.string() : display_name;
  return ParsePoseList(ReadTextFile(path, name), format, name);
}

std::string PoseFileFormatName(PoseFileFormat format) { return format == PoseFileFormat::kCsv ? "csv" : "tum"; }

}  // namespace lt

#include "pipeline/scan_output.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"

namespace lt {

namespace {

constexpr const char* kCsvHeader = "u,v,width,strength,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world";

void AppendPoint(std::string* out, const std::optional<Eigen::Vector3d>& p, const char* format) {
  char buf[128];
  for (int i = 0; i < 3; ++i) {
    out->push_back(',');
    if (p) {
      int len = std::snprintf(buf, sizeof buf, format, (*p)[i]);
      out->append(buf, size_t(len));
    }
  }
}

template <typename T>
void AppendLittleEndian(std::string* out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
  out->append(bytes, sizeof(T));
}

}  // namespace

std::string FormatScanCsv(const std::vector<ScanPoint>& points) {
  std::string out = std::string(kCsvHeader) + "\n";
  out.reserve(out.size() + points.size() * 120);
  char buf[160];
  for (const ScanPoint& s : points) {
    const StripePoint& p = s.pixel;
    int len = std::snprintf(buf, sizeof buf, "%.5f,%.5f,%.3f,%.6g,%d", p.u, p.v, p.width, p.strength, p.plane);
    out.append(buf, size_t(len));
    AppendPoint(&out, s.p_in_cam, "%.10g");   // 0.1 nm at 1 m
    AppendPoint(&out, s.p_in_world, "%.12g");  // 1 nm at 100 m
    out.push_back('\n');
  }
  return out;
}

void WriteScanCsv(const std::filesystem::path& path, const std::vector<ScanPoint>& points) {
  WriteFileAtomically(path, FormatScanCsv(points));
}

std::vector<ScanPoint> ReadScanCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot open");
  std::string line;
  if (!std::getline(in, line) || (line != kCsvHeader && line != std::string(kCsvHeader) + "\r")) {
    throw InputError(path.string() + ":1", std::string("expected the header ") + kCsvHeader);
  }
  std::vector<ScanPoint> points;
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::string where = path.string() + ":" + std::to_string(line_no);
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string field; std::getline(ss, field, ',');) f.push_back(field);
    if (!line.empty() && line.back() == ',') f.push_back("");
    if (f.size() != 11) throw InputError(where, "expected 11 fields, got " + std::to_string(f.size()));
    auto number = [&](size_t k) {
      char* end = nullptr;
      double v = std::strtod(f[k].c_str(), &end);
      if (f[k].empty() || *end != '\0' || !std::isfinite(v)) {
        throw InputError(where, "field " + std::to_string(k + 1) + " is not a finite number: '" + f[k] + "'");
      }
      return v;
    };
    auto point = [&](size_t k) -> std::optional<Eigen::Vector3d> {
      if (f[k].empty() && f[k + 1].empty() && f[k + 2].empty()) return std::nullopt;
      return Eigen::Vector3d(number(k), number(k + 1), number(k + 2));
    };
    ScanPoint s;
    s.pixel.u = number(0);
    s.pixel.v = number(1);
    s.pixel.width = number(2);
    s.pixel.strength = number(3);
    const double plane = number(4);
    if (plane != std::floor(plane) || plane < -1 || plane > 1e6) {
      throw InputError(where, "plane must be an integer >= -1, got '" + f[4] + "'");
    }
    s.pixel.plane = int(plane);
    s.p_in_cam = point(5);
    s.p_in_world = point(8);
    points.push_back(s);
  }
  return points;
}

std::string FormatPly(const PointCloud& cloud) {
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment lasertwin scan: laser stripe points, metres, " +
      std::string(cloud.world_frame ? "world frame" : "camera frame (some frames have no pose)") +
      "\nelement vertex " + std::to_string(cloud.points.size()) +
      "\nproperty double x\nproperty double y\nproperty double z\nproperty int frame\nproperty int plane\n";
  if (cloud.has_label) out += "property int label\n";
  if (cloud.has_colour) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "end_header\n";
  const size_t record = 3 * 8 + 2 * 4 + (cloud.has_label ? 4 : 0) + (cloud.has_colour ? 3 : 0);
  out.reserve(out.size() + cloud.points.size() * record);
  for (const CloudPoint& p : cloud.points) {
    if (!p.p.allFinite()) throw std::invalid_argument("FormatPly: a point is not finite");
    for (int i = 0; i < 3; ++i) AppendLittleEndian(&out, p.p[i]);
    AppendLittleEndian(&out, int32_t(p.frame));
    AppendLittleEndian(&out, int32_t(p.plane));
    if (cloud.has_label) AppendLittleEndian(&out, int32_t(p.label));
    if (cloud.has_colour) out.append(reinterpret_cast<const char*>(p.rgb.data()), 3);
  }
  return out;
}

void WritePly(const std::filesystem::path& path, const PointCloud& cloud) {
  WriteFileAtomically(path, FormatPly(cloud));
}

}  // namespace lt

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
#include "core/text_fields.h"

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
    const std::vector<std::string_view> f = SplitFields(line, ',');
    if (f.size() != 11) throw InputError(where, "expected 11 fields, got " + std::to_string(f.size()));
    auto number = [&](size_t k) { return FiniteField(f, k, where); };
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
      throw InputError(where, "plane must be an integer >= -1, got '" + std::string(f[4]) + "'");
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

namespace lt {

PointCloud ReadPly(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open");
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const std::string end = "end_header\n";
  const size_t body = bytes.find(end);
  if (bytes.rfind("ply\nformat binary_little_endian 1.0\n", 0) != 0 || body == std::string::npos) {
    throw InputError(path.string(), "not a binary little-endian PLY file as lasertwin scan writes");
  }
  const std::string header = bytes.substr(0, body);
  const std::string base = "property double x\nproperty double y\nproperty double z\nproperty int frame\nproperty int plane\n";
  const size_t props = header.find(base);
  const size_t count_pos = header.find("element vertex ");
  if (props == std::string::npos || count_pos == std::string::npos) {
    throw InputError(path.string(), "the header lacks the vertex element or its x, y, z, frame, plane properties");
  }
  PointCloud cloud;
  std::string rest = header.substr(props + base.size());
  const std::string label = "property int label\n";
  const std::string colour = "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (rest.rfind(label, 0) == 0) {
    cloud.has_label = true;
    rest = rest.substr(label.size());
  }
  if (rest.rfind(colour, 0) == 0) {
    cloud.has_colour = true;
    rest = rest.substr(colour.size());
  }
  if (!rest.empty()) throw InputError(path.string(), "unexpected properties in the header: " + rest);
  cloud.world_frame = header.find("world frame") != std::string::npos;
  const unsigned long long count = std::strtoull(header.c_str() + count_pos + 15, nullptr, 10);
  const size_t record = 3 * 8 + 2 * 4 + (cloud.has_label ? 4 : 0) + (cloud.has_colour ? 3 : 0);
  if (bytes.size() - (body + end.size()) != count * record) {
    throw InputError(path.string(), "holds " + std::to_string(bytes.size() - body - end.size()) + " bytes of vertices, " +
                                        std::to_string(count) + " vertices need " + std::to_string(count * record));
  }
  auto read = [](const char* p, auto& v) {
    std::memcpy(&v, p, sizeof v);
    if constexpr (std::endian::native == std::endian::big) {
      auto* b = reinterpret_cast<char*>(&v);
      std::reverse(b, b + sizeof v);
    }
  };
  const char* p = bytes.data() + body + end.size();
  cloud.points.resize(count);
  for (CloudPoint& c : cloud.points) {
    for (int i = 0; i < 3; ++i) read(p + 8 * i, c.p[i]);
    int32_t frame, plane, label = -1;
    read(p + 24, frame);
    read(p + 28, plane);
    if (cloud.has_label) read(p + 32, label);
    c.frame = frame, c.plane = plane, c.label = label;
    if (cloud.has_colour) std::memcpy(c.rgb.data(), p + 32 + (cloud.has_label ? 4 : 0), 3);
    if (!c.p.allFinite()) throw InputError(path.string(), "a vertex is not finite");
    p += record;
  }
  return cloud;
}

}  // namespace lt

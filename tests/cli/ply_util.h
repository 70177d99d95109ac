// Reading the binary PLY clouds `lasertwin scan` writes (x, y, z doubles,
// frame and plane ints, then (runs with ground truth) int label and (runs with
// bright frames) uchar red, green, blue), for the command-line tests.
#pragma once

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_util.h"

namespace lt::test {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};
inline double Distance(const Vec3& a, const Vec3& b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }

struct PlyVertex {
  Vec3 p;
  int32_t frame = 0, plane = 0, label = -1;
  uint8_t rgb[3] = {0, 0, 0};
};
inline std::vector<PlyVertex> ReadPly(const std::filesystem::path& path, std::string* header_out = nullptr) {
  const std::string bytes = ReadFile(path);
  const std::string end = "end_header\n";
  const size_t body = bytes.find(end);
  if (body == std::string::npos) {
    ADD_FAILURE() << "no end_header in " << path;
    return {};
  }
  const std::string header = bytes.substr(0, body + end.size());
  if (header_out) *header_out = header;
  EXPECT_THAT(header, ::testing::StartsWith("ply\nformat binary_little_endian 1.0\n"));
  EXPECT_THAT(header, ::testing::HasSubstr("property double x\nproperty double y\nproperty double z\nproperty int frame\n"
                                "property int plane\n"));
  const bool has_label = header.find("property int label\n") != std::string::npos;
  const bool has_colour = header.find("property uchar red\nproperty uchar green\nproperty uchar blue\n") != std::string::npos;
  const size_t pos = header.find("element vertex ");
  const size_t count = std::stoul(header.substr(pos + 15));
  const size_t record = 3 * 8 + 2 * 4 + (has_label ? 4 : 0) + (has_colour ? 3 : 0);
  EXPECT_EQ(bytes.size(), body + end.size() + count * record);
  std::vector<PlyVertex> out;
  const char* p = bytes.data() + body + end.size();
  for (size_t i = 0; i < count && p + record <= bytes.data() + bytes.size(); ++i, p += record) {
    PlyVertex v;  // the test machine is little-endian, like the file
    std::memcpy(&v.p.x, p, 8);
    std::memcpy(&v.p.y, p + 8, 8);
    std::memcpy(&v.p.z, p + 16, 8);
    std::memcpy(&v.frame, p + 24, 4);
    std::memcpy(&v.plane, p + 28, 4);
    if (has_label) std::memcpy(&v.label, p + 32, 4);
    if (has_colour) std::memcpy(v.rgb, p + 32 + (has_label ? 4 : 0), 3);
    out.push_back(v);
  }
  return out;
}

}  // namespace lt::test

// Where a pose file's values are (pose_file.h): the layout of its columns, from a header
// naming them or from the count of numbers per row. Internal to pose_file.cpp; defined in
// pose_file_layout.cpp.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/pose_file.h"
#include "pipeline/pose_file_names.h"

namespace lt::pose_file_detail {

// What a rotation's columns hold.
// kMatrixColumns: a 4x4 matrix in named columns, Layout::m.
enum class Rotation { kQuaternion, kRotationVector, kKukaAbc, kMatrix3x4, kMatrix4x4, kMatrixColumns };

// Where each value of a row is: columns of x y z, and of the rotation's values
// (quaternion: x y z w; rotation vector: x y z; KUKA: a b c).
struct Layout {
  Rotation rotation = Rotation::kQuaternion;
  size_t fields = 0;
  int t[3] = {-1, -1, -1};
  int time = -1;            // the column of the time, -1: none
  int time_nanosec = -1;    // the column of its nanoseconds, when written in two (ROS's stamp.sec, stamp.nanosec)
  double time_to_s = 1.0;   // its unit
  bool time_unit_known = false;  // said by the name (or the log's format); else from the values' size
  int body = -1;            // the column naming the body (frame) whose pose the row is: ROS's child_frame_id; -1: none
  std::string body_column;  // its name as written
  int r[4] = {-1, -1, -1, -1};
  int m[16] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};  // kMatrixColumns: row-major element's column
  std::string form;
};

// The layout a header names; nullopt when `strict` is false and a name is not known.
std::optional<Layout> HeaderLayout(const std::vector<std::string_view>& fields, const std::string& where, bool strict,
                                   std::optional<PoseUnits>* header_units);

// The layout of rows of `n` numbers without a header (TUM, KITTI's matrices, x y z +
// quaternion in the order `o` gives).
Layout HeaderlessLayout(size_t n, char separator, const PoseFileOptions& o, const std::string& where);

}  // namespace lt::pose_file_detail

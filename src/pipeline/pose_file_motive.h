// OptiTrack Motive's CSV export as a pose file (pose_file.h): the rows above its data
// (take settings; Type, Name, ID and Parent rows; the Rotation/Position row; the column
// names "Frame,Time (Seconds),X,Y,Z,W,X,Y,Z,...") read into one header line naming the
// chosen rigid body's columns (the others' columns unnamed, so skipped). Internal to
// pose_file.cpp.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace lt::pose_file_detail {

// Bodies named in a message about a file of several (and how many more).
constexpr size_t kBodiesListed = 12;

struct MotiveText {
  std::string text;  // the file with its rows above the data blank and one header line in place of its column names
  std::string body;  // the rigid body's name
};

// Nullopt when `text` is no Motive export (its first row does not start "Format
// Version"). The rigid body is `body` (--pose-body), else the export's one. Throws
// lt::InputError naming `name` and the line when the export holds no rigid body,
// several and no `body`, no rigid body named `body` (the error lists those it holds),
// or its rotations or lengths in a form not read.
std::optional<MotiveText> MotiveAsOneHeader(const std::string& text, const std::string& name,
                                            const std::optional<std::string>& body);

}  // namespace lt::pose_file_detail

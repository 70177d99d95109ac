// OptiTrack Motive's CSV export read as one header line (pose_file_motive.h).
#include "pipeline/pose_file_motive.h"

#include <algorithm>
#include <map>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/pose_file_layout.h"

namespace lt::pose_file_detail {

namespace {

struct Line {
  size_t begin = 0, end = 0;  // the line's characters in the text
  int number = 0;
  std::vector<std::string_view> fields;
};

std::string Field(const Line& l, size_t k) { return k < l.fields.size() ? Lower(TrimBlanks(l.fields[k])) : ""; }

// The row of the column names, "Frame,Time (Seconds),X,Y,Z,...": the data follow.
bool ColumnNames(const Line& l) { return Field(l, 0) == "frame" && Field(l, 1).rfind("time", 0) == 0; }

}  // namespace

std::optional<MotiveText> MotiveAsOneHeader(const std::string& text, const std::string& name,
                                            const std::optional<std::string>& chosen_body) {
  std::vector<Line> lines;
  size_t pos = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  for (int number = 1; pos < text.size(); ++number) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    Line l{pos, end, number, {}};
    const std::string_view row = TrimBlanks(std::string_view(text).substr(pos, end - pos));
    if (!row.empty()) l.fields = SplitFields(row, ',');
    lines.push_back(l);
    pos = end + 1;
    if (lines.size() == 1 && Field(l, 0) != "format version") return std::nullopt;
    if (ColumnNames(l)) break;
  }
  if (lines.empty()) return std::nullopt;
  auto where = [&](const Line& l) { return name + ":" + std::to_string(l.number); };
  // The take's settings: "Rotation Type,Quaternion,Length Units,Meters".
  std::map<std::string, std::string> settings;
  for (size_t k = 0; k + 1 < lines[0].fields.size(); k += 2) settings[Field(lines[0], k)] = Field(lines[0], k + 1);
  const std::string rotation = settings["rotation type"], length = settings["length units"];
  if (!rotation.empty() && rotation != "quaternion") {
    throw InputError(where(lines[0]), "an OptiTrack Motive export with Rotation Type " + rotation +
                                          ": export the rotations as quaternions");
  }
  const char* unit = length.empty() || length == "meters" ? "m" : length == "millimeters" ? "mm" : nullptr;
  if (!unit) throw InputError(where(lines[0]), "an OptiTrack Motive export in " + length + ": export in meters or millimeters");
  // The rows above the data, by their labels.
  const size_t columns = lines.size() - 1;  // the reading above stopped at the column names, if any
  if (!ColumnNames(lines[columns]) || columns < 2) {
    throw InputError(where(lines[0]), "an OptiTrack Motive export without its 'Frame,Time (Seconds),X,Y,Z,...' row");
  }
  const Line *type = nullptr, *body = nullptr;
  for (size_t k = 1; k < columns; ++k) {
    if (Field(lines[k], 1) == "type") type = &lines[k];
    if (Field(lines[k], 1) == "name") body = &lines[k];
  }
  const Line& kind = lines[columns - 1];  // ",,Rotation,Rotation,...,Position,..."
  const Line& axes = lines[columns];
  if (!type || !body) throw InputError(where(axes), "an OptiTrack Motive export without its Type and Name rows");
  // The rigid bodies' rotation and position columns: the chosen one's, the others' skipped.
  auto body_of = [&](size_t c) {
    return std::string(TrimBlanks(c < body->fields.size() ? body->fields[c] : std::string_view()));
  };
  std::vector<std::string> bodies;
  for (size_t c = 2; c < axes.fields.size(); ++c) {
    const std::string k = Field(kind, c);
    if (Field(*type, c) != "rigid body" || (k != "rotation" && k != "position")) continue;
    const std::string b = body_of(c);
    if (std::find(bodies.begin(), bodies.end(), b) == bodies.end()) bodies.push_back(b);
  }
  if (bodies.empty()) {
    throw InputError(where(*type), "an OptiTrack Motive export without a rigid body (markers only): export the "
                                   "scanner's rigid body");
  }
  const std::string listed = ListFirst(bodies, kBodiesListed, '\'');
  if (chosen_body && std::find(bodies.begin(), bodies.end(), *chosen_body) == bodies.end()) {
    throw InputError(where(*body), "no rigid body '" + *chosen_body + "' in this OptiTrack Motive export: its rigid " +
                                       (bodies.size() == 1 ? "body is " : "bodies are ") + listed);
  }
  if (!chosen_body && bodies.size() > 1) {
    throw InputError(where(*body), "an OptiTrack Motive export of several rigid bodies: give --pose-body: " + listed);
  }
  const std::string chosen = chosen_body ? *chosen_body : bodies[0];
  std::vector<std::string> names(axes.fields.size());
  names[0] = "frame";
  names[1] = "time [s]";
  for (size_t c = 2; c < axes.fields.size(); ++c) {
    if (Field(*type, c) != "rigid body" || body_of(c) != chosen) continue;
    const std::string k = Field(kind, c), a = Field(axes, c);
    if (k == "rotation" || k == "position") names[c] = k == "rotation" ? "q" + a : a + " [" + unit + "]";
  }
  MotiveText out{text, chosen};
  for (size_t k = 0; k < columns; ++k) {
    for (size_t i = lines[k].begin; i < lines[k].end; ++i) out.text[i] = ' ';
  }
  std::string header;
  for (size_t c = 0; c < names.size(); ++c) header += (c ? "," : "") + names[c];
  out.text.replace(axes.begin, axes.end - axes.begin, header);
  return out;
}

}  // namespace lt::pose_file_detail

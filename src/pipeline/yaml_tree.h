// The one YAML reader of lasertwin: OpenCV's FileStorage YAML
// (pipeline/opencv_yaml.h reads its entries from this tree) and the camera
// files other tools write (ROS camera_info, Kalibr camchain, camodocal;
// pipeline/camera_file_formats.h). Block mappings and sequences by
// indentation, flow sequences [a, b] and mappings {a: 1} (which may span
// lines), a value on the line after its key, plain and quoted scalars (quoted
// keys too), literal and folded block scalars (| >, with chomping and
// indentation indicators), anchors and aliases (&a, *a), tags
// (`!!opencv-matrix`, kept on the node), `#` comments, a BOM, CR LF line ends,
// leading directives (`%YAML:1.0`, `%YAML 1.0`) and `---` / `...` document
// markers (of several documents, the first is read). Tabs in indentation and
// plain scalars over several lines are refused. Errors are lt::InputError
// naming "file:line".
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace lt {

struct YamlNode {
  enum class Kind { kNull, kScalar, kMap, kSeq };
  Kind kind = Kind::kNull;
  int line = 0;         // 1-based line: of the node, or of the key whose block value it is
  std::string tag;      // e.g. "!!opencv-matrix", or empty
  std::string scalar;   // kScalar: the value (unquoted)
  bool quoted = false;  // kScalar: written in quotes (a string, never a number)
  std::vector<std::pair<std::string, YamlNode>> map;  // kMap, in file order
  std::vector<YamlNode> seq;                          // kSeq

  // The value of `key` in a map (nullptr if absent or not a map).
  const YamlNode* Find(const std::string& key) const;
};

// A line of the text, numbered from 1.
struct YamlLine {
  int no = 1;
  std::string text;  // without indentation, comment and trailing blanks
};

// Parses a YAML text whose top level is a mapping (an empty text gives an
// empty map). `file` names the text in errors. `first`, when given, receives
// the first line that is neither blank nor a comment (a directive such as
// "%YAML:1.0", "---" or the first key; line 1 and "" for an empty text).
YamlNode ParseYamlTree(const std::string& text, const std::string& file, YamlLine* first = nullptr);

}  // namespace lt

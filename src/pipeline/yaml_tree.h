// The one YAML reader of lasertwin: OpenCV's FileStorage YAML
// (pipeline/opencv_yaml.h) and the camera files of other tools (ROS, Kalibr,
// camodocal; pipeline/camera_file_formats.h). Block and flow collections
// (flow ones may span lines), a value on the line after its key, plain and
// quoted scalars and keys, block scalars (| >), anchors and aliases, tags
// (`!!opencv-matrix`, kept on the node), `#` comments, BOM, CR LF, leading
// directives (`%YAML:1.0`) and `---` / `...` (of several documents, the
// first). Tabs in indentation and plain scalars over several lines are
// refused. Errors are lt::InputError naming "file:line".
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

  // Defined where YamlNode is complete (yaml_tree.cpp): Clang 14 with libstdc++ 12
  // refuses the implicit ones (std::pair of the incomplete YamlNode in `map`).
  YamlNode();
  YamlNode(const YamlNode&);
  YamlNode(YamlNode&&) noexcept;
  YamlNode& operator=(const YamlNode&);
  YamlNode& operator=(YamlNode&&) noexcept;
  ~YamlNode();

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

// A small YAML reader for the camera files other tools write (ROS
// camera_info, Kalibr camchain, camodocal; pipeline/camera_file_formats.h):
// block mappings and sequences by indentation, flow sequences [a, b] and
// mappings {a: 1} (which may span lines), plain and quoted scalars, tags
// (`!!opencv-matrix`, kept on the node), `#` comments, leading directives
// (`%YAML:1.0`, `%YAML 1.0`) and `---` / `...` document markers. Anchors,
// aliases, block scalars (| >) and multi-line plain scalars are refused.
// Errors are lt::InputError naming "file:line".
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

// Parses a YAML text whose top level is a mapping (an empty text gives an
// empty map). `file` names the text in errors.
YamlNode ParseYamlTree(const std::string& text, const std::string& file);

}  // namespace lt

// The lines of a YAML text as the tree reader (pipeline/yaml_tree.h) parses
// them: its first document's content lines, each with its indentation and
// without its comment, and every raw line (block scalars keep their own
// indentation). BOM, CR LF, leading directives (`%YAML:1.0`) and `---` / `...`
// are handled here; tabs in indentation are refused.
#pragma once

#include <string>
#include <vector>

#include "pipeline/yaml_tree.h"

namespace lt {

struct YamlContentLine {
  int no = 0;          // 1-based line number
  int indent = 0;      // spaces before the text
  std::string text;    // without indentation, comment and trailing blanks
};

struct YamlLines {
  std::vector<std::string> raw;          // every line read, as written (raw[k] is line k + 1)
  std::vector<YamlContentLine> content;  // the first document's lines that hold something
};

// Splits `text` (named `file` in errors, lt::InputError "file:line"). `first`,
// when given, receives the first line that is neither blank nor a comment.
YamlLines SplitYamlLines(const std::string& text, const std::string& file, YamlLine* first);

}  // namespace lt

#include "pipeline/yaml_lines.h"

#include <sstream>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/yaml_scalar.h"

namespace lt {

YamlLines SplitYamlLines(const std::string& text, const std::string& file, YamlLine* first) {
  auto fail = [&](int line, const std::string& message) {
    throw InputError(file + ":" + std::to_string(line), message);
  };
  YamlLines out;
  std::istringstream in(text);
  std::string raw;
  int no = 0;
  bool content = false;
  while (std::getline(in, raw)) {
    ++no;
    if (no == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw = raw.substr(3);
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    out.raw.push_back(raw);
    size_t indent = 0;
    while (indent < raw.size() && (raw[indent] == ' ' || raw[indent] == '\t')) {
      if (raw[indent] == '\t') fail(no, "tab in indentation (YAML indents with spaces)");
      ++indent;
    }
    const std::string body(TrimBlanks(StripYamlComment(raw.substr(indent))));
    if (body.empty()) continue;
    if (first && first->text.empty()) *first = {no, body};
    if (indent == 0 && body[0] == '%') {
      if (content) fail(no, "a directive ('" + body + "') after the document's start");
      continue;
    }
    if (indent == 0 && (body == "---" || body.rfind("--- ", 0) == 0)) {
      if (body != "---") fail(no, "expected '---' alone on its line");
      if (content) break;  // a second document (rostopic echo ends each message with ---): only the first
      content = true;
      continue;
    }
    if (indent == 0 && body == "...") break;
    content = true;
    out.content.push_back({no, int(indent), body});
  }
  return out;
}

}  // namespace lt

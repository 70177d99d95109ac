#include "pipeline/yaml_tree.h"

#include <set>
#include <sstream>

#include "core/error.h"

namespace lt {

namespace {

struct Line {
  int no = 0;
  int indent = 0;
  std::string text;  // without indentation, comment and trailing blanks
};

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// A quote opens a quoted scalar where a value or key can start.
bool OpensQuote(const std::string& s, size_t i) {
  if (s[i] != '"' && s[i] != '\'') return false;
  if (i == 0) return true;
  const char p = s[i - 1];
  return p == ' ' || p == '\t' || p == '[' || p == '{' || p == ',' || p == ':' || p == '-';
}

// Drops a `#` comment (at the start or after a blank, outside quotes).
std::string StripComment(const std::string& s) {
  char quote = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote) {
      if (quote == '"' && c == '\\') {
        ++i;
      } else if (c == quote) {
        if (quote == '\'' && i + 1 < s.size() && s[i + 1] == '\'') {
          ++i;
        } else {
          quote = 0;
        }
      }
    } else if (OpensQuote(s, i)) {
      quote = c;
    } else if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) {
      return s.substr(0, i);
    }
  }
  return s;
}

bool IsSeqItem(const std::string& t) { return t == "-" || t.rfind("- ", 0) == 0; }

class TreeParser {
 public:
  TreeParser(const std::string& text, std::string file) : file_(std::move(file)) {
    std::istringstream in(text);
    std::string raw;
    int no = 0;
    bool content = false;
    while (std::getline(in, raw)) {
      ++no;
      if (no == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw = raw.substr(3);
      if (!raw.empty() && raw.back() == '\r') raw.pop_back();
      size_t indent = 0;
      while (indent < raw.size() && (raw[indent] == ' ' || raw[indent] == '\t')) {
        if (raw[indent] == '\t') Fail(no, "tab in indentation (YAML indents with spaces)");
        ++indent;
      }
      const std::string body = Trim(StripComment(raw.substr(indent)));
      if (body.empty()) continue;
      if (indent == 0 && body[0] == '%') {
        if (content) Fail(no, "a directive ('" + body + "') after the document's start");
        continue;
      }
      if (indent == 0 && (body == "---" || body.rfind("--- ", 0) == 0)) {
        if (body != "---") Fail(no, "expected '---' alone on its line");
        if (content) break;  // a second document (rostopic echo ends each message with ---): only the first
        content = true;
        continue;
      }
      if (indent == 0 && body == "...") break;
      content = true;
      lines_.push_back({no, int(indent), body});
    }
  }

  YamlNode Run() {
    size_t i = 0;
    YamlNode root;
    root.kind = YamlNode::Kind::kMap;
    root.line = 1;
    if (lines_.empty()) return root;
    if (lines_[0].indent != 0) Fail(lines_[0].no, "unexpected indentation (expected a top-level 'key: value')");
    if (IsSeqItem(lines_[0].text)) Fail(lines_[0].no, "the top level is a sequence (expected 'key: value' lines)");
    root = ParseMap(i, 0);
    if (i < lines_.size()) Fail(lines_[i].no, "unexpected indentation");
    return root;
  }

 private:
  [[noreturn]] void Fail(int line, const std::string& message) const {
    throw InputError(file_ + ":" + std::to_string(line), message);
  }

  // Splits "key: rest" at the first ':' followed by a blank or the end, outside quotes.
  bool SplitKey(const std::string& t, int line, std::string* key, std::string* rest) const {
    size_t i = 0;
    if (!t.empty() && (t[0] == '"' || t[0] == '\'')) {
      size_t end = 0;
      *key = QuotedScalar(t, 0, line, &end);
      i = end;
      while (i < t.size() && t[i] == ' ') ++i;
      if (i >= t.size() || t[i] != ':') return false;
    } else {
      for (; i < t.size(); ++i) {
        if (t[i] == ':' && (i + 1 == t.size() || t[i + 1] == ' ' || t[i + 1] == '\t')) break;
      }
      if (i >= t.size()) return false;
      *key = Trim(t.substr(0, i));
      if (key->empty()) return false;
    }
    *rest = Trim(t.substr(i + 1));
    return true;
  }

  // The quoted scalar starting at s[begin]; *end is just past its closing quote.
  std::string QuotedScalar(const std::string& s, size_t begin, int line, size_t* end) const {
    const char q = s[begin];
    std::string v;
    for (size_t k = begin + 1; k < s.size(); ++k) {
      const char c = s[k];
      if (q == '\'' && c == '\'' && k + 1 < s.size() && s[k + 1] == '\'') {
        v += '\'';
        ++k;
      } else if (q == '"' && c == '\\' && k + 1 < s.size()) {
        const char n = s[++k];
        v += n == 'n' ? '\n' : n == 't' ? '\t' : n;
      } else if (c == q) {
        *end = k + 1;
        return v;
      } else {
        v += c;
      }
    }
    Fail(line, "unterminated quoted string");
  }

  YamlNode ParseMap(size_t& i, int indent) {
    YamlNode node;
    node.kind = YamlNode::Kind::kMap;
    node.line = lines_[i].no;
    std::set<std::string> seen;
    while (i < lines_.size() && lines_[i].indent >= indent) {
      const Line l = lines_[i];
      if (l.indent > indent) Fail(l.no, "unexpected indentation");
      if (IsSeqItem(l.text)) Fail(l.no, "a sequence item where 'key: value' was expected");
      std::string key, rest;
      if (!SplitKey(l.text, l.no, &key, &rest)) Fail(l.no, "expected 'key: value', got '" + l.text + "'");
      if (!seen.insert(key).second) Fail(l.no, "duplicate key '" + key + "'");
      ++i;
      node.map.emplace_back(key, ParseValue(key, rest, l.no, indent, i, true));
    }
    return node;
  }

  YamlNode ParseSeq(size_t& i, int indent) {
    YamlNode node;
    node.kind = YamlNode::Kind::kSeq;
    node.line = lines_[i].no;
    while (i < lines_.size() && lines_[i].indent == indent && IsSeqItem(lines_[i].text)) {
      Line& l = lines_[i];
      const size_t offset = l.text.find_first_not_of(' ', 1);
      const std::string rest = offset == std::string::npos ? "" : l.text.substr(offset);
      std::string key, value;
      if (!rest.empty() && rest[0] != '[' && rest[0] != '{' && SplitKey(rest, l.no, &key, &value)) {
        // "- key: value": a mapping whose keys line up with this key.
        l.indent = indent + int(offset);
        l.text = rest;
        node.seq.push_back(ParseMap(i, l.indent));
        continue;
      }
      const int no = l.no;
      ++i;
      node.seq.push_back(ParseValue("-", rest, no, indent, i, false));
    }
    return node;
  }

  // The value after "key:" (or "-") on line `no`, whose block children are
  // the lines from i indented more than `indent` (for a key, a sequence at the
  // key's own indentation too).
  YamlNode ParseValue(const std::string& key, std::string rest, int no, int indent, size_t& i, bool in_map) {
    std::string tag;
    if (!rest.empty() && rest[0] == '!') {
      const size_t sp = rest.find(' ');
      tag = rest.substr(0, sp);
      rest = sp == std::string::npos ? "" : Trim(rest.substr(sp));
    }
    if (!rest.empty() && (rest[0] == '&' || rest[0] == '*')) {
      Fail(no, "anchors and aliases are not supported ('" + key + "')");
    }
    if (!rest.empty() && (rest[0] == '|' || rest[0] == '>')) {
      Fail(no, "block scalars (| or >) are not supported ('" + key + "')");
    }
    YamlNode node;
    if (rest.empty()) {
      if (i < lines_.size() && lines_[i].indent > indent) {
        const int child = lines_[i].indent;
        node = IsSeqItem(lines_[i].text) ? ParseSeq(i, child) : ParseMap(i, child);
      } else if (in_map && i < lines_.size() && lines_[i].indent == indent && IsSeqItem(lines_[i].text)) {
        node = ParseSeq(i, indent);
      }
      node.line = no;  // a block value's errors name its key's line
      node.tag = tag;
      return node;
    }
    if (rest[0] == '[' || rest[0] == '{') {
      // A flow collection may continue on the following lines until it closes.
      std::string text = rest;
      while (!Balanced(text, no) && i < lines_.size()) text += " " + lines_[i++].text;
      size_t pos = 0;
      node = ParseFlow(text, pos, no, false);
      SkipBlanks(text, pos);
      if (pos < text.size()) Fail(no, "unexpected text after the value of '" + key + "': '" + text.substr(pos) + "'");
    } else {
      node.kind = YamlNode::Kind::kScalar;
      node.line = no;
      if (rest[0] == '"' || rest[0] == '\'') {
        size_t end = 0;
        node.scalar = QuotedScalar(rest, 0, no, &end);
        node.quoted = true;
        if (!Trim(rest.substr(end)).empty()) {
          Fail(no, "unexpected text after the quoted string: '" + Trim(rest.substr(end)) + "'");
        }
      } else {
        node.scalar = rest;
      }
      if (i < lines_.size() && lines_[i].indent > indent) {
        Fail(lines_[i].no, "unexpected indented line after the value of '" + key +
                               "' (values that span lines are supported inside [ ] and { } only)");
      }
    }
    node.tag = tag;
    return node;
  }

  // Whether every [ and { of a flow text is closed (outside quotes).
  bool Balanced(const std::string& s, int no) const {
    int depth = 0;
    for (size_t k = 0; k < s.size(); ++k) {
      if (OpensQuote(s, k)) {
        const size_t close = s.find(s[k], k + 1);
        if (close == std::string::npos) return false;
        k = close;
      } else if (s[k] == '[' || s[k] == '{') {
        ++depth;
      } else if (s[k] == ']' || s[k] == '}') {
        if (--depth < 0) Fail(no, "unbalanced '" + std::string(1, s[k]) + "'");
      }
    }
    return depth == 0;
  }

  static void SkipBlanks(const std::string& s, size_t& pos) {
    while (pos < s.size() && (s[pos] == ' ' || s[pos] == '\t')) ++pos;
  }

  YamlNode ParseFlow(const std::string& s, size_t& pos, int no, bool key) {
    SkipBlanks(s, pos);
    YamlNode node;
    node.line = no;
    if (pos >= s.size()) Fail(no, "missing value in '" + s + "'");
    const char c = s[pos];
    if (c == '[' || c == '{') {
      const char close = c == '[' ? ']' : '}';
      node.kind = c == '[' ? YamlNode::Kind::kSeq : YamlNode::Kind::kMap;
      ++pos;
      for (;;) {
        SkipBlanks(s, pos);
        if (pos < s.size() && s[pos] == close) {
          ++pos;
          return node;
        }
        if (node.kind == YamlNode::Kind::kSeq) {
          node.seq.push_back(ParseFlow(s, pos, no, false));
        } else {
          const YamlNode k = ParseFlow(s, pos, no, true);
          SkipBlanks(s, pos);
          if (pos >= s.size() || s[pos] != ':') Fail(no, "expected ':' after the key '" + k.scalar + "' in { }");
          ++pos;
          node.map.emplace_back(k.scalar, ParseFlow(s, pos, no, false));
        }
        SkipBlanks(s, pos);
        if (pos < s.size() && s[pos] == ',') {
          ++pos;
        } else if (pos >= s.size() || s[pos] != close) {
          Fail(no, std::string("expected ',' or '") + close + "' in '" + s + "'");
        }
      }
    }
    node.kind = YamlNode::Kind::kScalar;
    if (c == '"' || c == '\'') {
      size_t end = 0;
      node.scalar = QuotedScalar(s, pos, no, &end);
      node.quoted = true;
      pos = end;
      return node;
    }
    const size_t begin = pos;
    while (pos < s.size() && s[pos] != ',' && s[pos] != ']' && s[pos] != '}' &&
           !(key && s[pos] == ':' && (pos + 1 == s.size() || s[pos + 1] == ' '))) {
      ++pos;
    }
    node.scalar = Trim(s.substr(begin, pos - begin));
    if (node.scalar.empty()) Fail(no, "empty value in '" + s + "'");
    return node;
  }

  std::string file_;
  std::vector<Line> lines_;
};

}  // namespace

const YamlNode* YamlNode::Find(const std::string& key) const {
  for (const auto& [k, v] : map) {
    if (k == key) return &v;
  }
  return nullptr;
}

YamlNode ParseYamlTree(const std::string& text, const std::string& file) { return TreeParser(text, file).Run(); }

}  // namespace lt

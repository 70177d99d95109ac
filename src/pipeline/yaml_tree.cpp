#include "pipeline/yaml_tree.h"

#include <map>
#include <set>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/yaml_lines.h"
#include "pipeline/yaml_scalar.h"

namespace lt {

namespace {

using Line = YamlContentLine;

std::string Trim(const std::string& s) { return std::string(TrimBlanks(s)); }

// Text quoted in a message: its first 80 characters (a flow collection over
// thousands of lines is one text).
std::string Shown(const std::string& s) { return s.size() <= 80 ? s : s.substr(0, 80) + "..."; }

bool IsSeqItem(const std::string& t) { return t == "-" || t.rfind("- ", 0) == 0; }

class TreeParser {
 public:
  TreeParser(const std::string& text, std::string file, YamlLine* first) : file_(std::move(file)) {
    YamlLines lines = SplitYamlLines(text, file_, first);
    raw_ = std::move(lines.raw);
    lines_ = std::move(lines.content);
  }

  YamlNode Run() {
    size_t i = 0;
    YamlNode root;
    root.kind = YamlNode::Kind::kMap;
    root.line = 1;
    if (lines_.empty()) return root;
    if (lines_[0].indent != 0) Fail(lines_[0].no, "unexpected indentation (expected a top-level 'key: value')");
    if (IsSeqItem(lines_[0].text)) {
      Fail(lines_[0].no, "top-level sequences are not supported (expected 'key: value' lines)");
    }
    root = ParseMap(i, 0);
    if (i < lines_.size()) Fail(lines_[i].no, "unexpected indentation");
    return root;
  }

 private:
  [[noreturn]] void Fail(int line, const std::string& message) const {
    throw InputError(file_ + ":" + std::to_string(line), message);
  }

  // One level of nesting (a block or flow collection) while it is read: deeper
  // than kMaxDepth is an error, not a stack overflow.
  class Nest {
   public:
    Nest(TreeParser* p, int line) : p_(p) {
      if (++p_->depth_ > kMaxDepth) {
        p_->Fail(line, "collections nested deeper than " + std::to_string(kMaxDepth) + " levels");
      }
    }
    ~Nest() { --p_->depth_; }
    Nest(const Nest&) = delete;
    Nest& operator=(const Nest&) = delete;

   private:
    TreeParser* p_;
  };

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
    std::string value;
    if (!ReadQuotedScalar(s, begin, &value, end)) Fail(line, "unterminated quoted string");
    return value;
  }

  // The block mapping at lines_[i] (the value of `parent`, "" at the top level).
  YamlNode ParseMap(size_t& i, int indent, const std::string& parent = "") {
    const std::string in = parent.empty() ? "" : " in '" + parent + "'";
    const Nest nest(this, lines_[i].no);
    YamlNode node;
    node.kind = YamlNode::Kind::kMap;
    node.line = lines_[i].no;
    std::set<std::string> seen;
    while (i < lines_.size() && lines_[i].indent >= indent) {
      const Line l = lines_[i];
      if (l.indent > indent) Fail(l.no, "unexpected indentation");
      if (IsSeqItem(l.text)) Fail(l.no, "a sequence item where 'key: value' was expected" + in);
      std::string key, rest;
      if (!SplitKey(l.text, l.no, &key, &rest)) Fail(l.no, "expected 'key: value'" + in + ", got '" + Shown(l.text) + "'");
      if (!seen.insert(key).second) Fail(l.no, "duplicate key '" + key + "'");
      ++i;
      node.map.emplace_back(key, ParseValue(key, rest, l.no, indent, i, true));
    }
    return node;
  }

  YamlNode ParseSeq(size_t& i, int indent) {
    const Nest nest(this, lines_[i].no);
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
    std::string tag, anchor;
    size_t start = 0;
    ReadProperties(rest, start, no, &tag, &anchor);
    rest = rest.substr(start);
    YamlNode node;
    if (rest.empty()) {
      if (i < lines_.size() && lines_[i].indent > indent) {
        const Line& l = lines_[i];
        std::string k, v;
        if (IsSeqItem(l.text)) {
          node = ParseSeq(i, l.indent);
        } else if (l.text[0] != '[' && l.text[0] != '{' && SplitKey(l.text, l.no, &k, &v)) {
          node = ParseMap(i, l.indent, key);
        } else {
          ++i;  // the value on the next line
          node = ParseValue(key, l.text, l.no, indent, i, false);
        }
      } else if (in_map && i < lines_.size() && lines_[i].indent == indent && IsSeqItem(lines_[i].text)) {
        node = ParseSeq(i, indent);
      }
      node.line = no;  // a block value's errors name its key's line
    } else if (rest[0] == '|' || rest[0] == '>') {
      node = BlockScalar(key, rest, no, indent, i);
    } else if (rest[0] == '[' || rest[0] == '{') {
      // A flow collection may continue on the following lines until it closes.
      std::string text = rest;
      FlowBalance balance;
      for (char extra = 0;;) {
        const bool closed = balance.Closed(text, &extra);
        if (extra) Fail(no, "unbalanced '" + std::string(1, extra) + "'");
        if (closed || i >= lines_.size()) break;
        text += ' ';
        text += lines_[i++].text;
      }
      size_t pos = 0;
      node = ParseFlow(text, pos, no, false);
      SkipBlanks(text, pos);
      if (pos < text.size()) Fail(no, "unexpected text after the value of '" + key + "': '" + Shown(text.substr(pos)) + "'");
    } else {
      if (rest[0] == '*') {
        size_t pos = 0;
        node = Alias(rest, pos, no);
        if (pos < rest.size()) Fail(no, "unexpected text after the alias: '" + Trim(rest.substr(pos)) + "'");
      } else if (rest[0] == '"' || rest[0] == '\'') {
        size_t end = 0;
        node.scalar = QuotedScalar(rest, 0, no, &end);
        node.quoted = true;
        if (!Trim(rest.substr(end)).empty()) {
          Fail(no, "unexpected text after the quoted string: '" + Trim(rest.substr(end)) + "'");
        }
      } else {
        node.scalar = rest;
      }
      if (node.kind == YamlNode::Kind::kNull) node.kind = YamlNode::Kind::kScalar;
      node.line = no;
      if (i < lines_.size() && lines_[i].indent > indent) {
        Fail(lines_[i].no, "unexpected indented line after the value of '" + key +
                               "' (values that span lines are supported inside [ ] and { } only)");
      }
    }
    return WithProperties(std::move(node), tag, anchor);
  }

  // The tag (!x) and anchor (&x) at s[pos], in either order, and the blanks after them.
  void ReadProperties(const std::string& s, size_t& pos, int no, std::string* tag, std::string* anchor) const {
    SkipBlanks(s, pos);
    while (pos < s.size() && ((s[pos] == '!' && tag->empty()) || (s[pos] == '&' && anchor->empty()))) {
      std::string* property = s[pos] == '!' ? tag : anchor;
      *property = Property(s, pos, no);
      SkipBlanks(s, pos);
    }
  }

  // A tag or an anchor's name (without its '&') at s[pos], up to a blank, ',', ']' or '}'.
  std::string Property(const std::string& s, size_t& pos, int no) const {
    const size_t begin = pos;
    while (pos < s.size() && s[pos] != ' ' && s[pos] != '\t' && s[pos] != ',' && s[pos] != ']' && s[pos] != '}') ++pos;
    if (pos == begin + 1) Fail(no, std::string("'") + s[begin] + "' without a name");
    return s[begin] == '&' ? s.substr(begin + 1, pos - begin - 1) : s.substr(begin, pos - begin);
  }

  // The node of the alias at s[pos] ("*name"): a copy of its anchor's.
  YamlNode Alias(const std::string& s, size_t& pos, int no) {
    const std::string name = Property(s, pos, no).substr(1);
    const auto it = anchors_.find(name);
    if (it == anchors_.end()) {
      Fail(no, "unknown alias '*" + name + "' (its anchor '&" + name + "' must come before it)");
    }
    // Aliases of aliases grow the tree exponentially with the text ("billion laughs").
    copied_ += it->second.size;
    if (copied_ > kMaxCopied) {
      Fail(no, "the aliases copy more than " + std::to_string(kMaxCopied) +
                   " nodes and characters (each alias copies its anchor's whole value)");
    }
    YamlNode node = it->second.node;
    node.line = no;
    return node;
  }

  // `node` with its tag, remembered under its anchor.
  YamlNode WithProperties(YamlNode node, const std::string& tag, const std::string& anchor) {
    if (!tag.empty()) node.tag = tag;
    if (!anchor.empty()) anchors_[anchor] = {node, Size(node)};
    return node;
  }

  // A literal (|) or folded (>) block scalar: `header` is its indicator line,
  // its text the raw lines after `no` that are blank or indented more than `indent`.
  YamlNode BlockScalar(const std::string& key, const std::string& header, int no, int indent, size_t& i) {
    char chomp = 0;
    int base = 0;
    for (size_t k = 1; k < header.size(); ++k) {
      if ((header[k] == '+' || header[k] == '-') && !chomp) {
        chomp = header[k];
      } else if (header[k] >= '1' && header[k] <= '9' && !base) {
        base = indent + (header[k] - '0');
      } else {
        Fail(no, "unexpected text after the block scalar's '" + header.substr(0, 1) + "': '" + header.substr(k) + "'");
      }
    }
    auto blank = [](const std::string& r) { return r.find_first_not_of(' ') == std::string::npos; };
    size_t end = size_t(no);  // raw_[k] is line k + 1: the block's lines are raw_[no, end)
    while (end < raw_.size() && (blank(raw_[end]) || int(raw_[end].find_first_not_of(' ')) > indent)) {
      if (!base && !blank(raw_[end])) base = int(raw_[end].find_first_not_of(' '));
      ++end;
    }
    std::vector<std::string> body;
    for (size_t k = size_t(no); k < end; ++k) {
      if (!blank(raw_[k]) && int(raw_[k].find_first_not_of(' ')) < base) {
        Fail(int(k) + 1, "a line of the block scalar '" + key + "' indented less than its first line");
      }
      body.push_back(blank(raw_[k]) ? "" : raw_[k].substr(size_t(base)));
    }
    while (i < lines_.size() && lines_[i].no <= int(end)) ++i;
    YamlNode node;
    node.kind = YamlNode::Kind::kScalar;
    node.line = no;
    node.scalar = BlockScalarText(body, header[0], chomp);
    node.quoted = true;  // a string, never a number
    return node;
  }

  static void SkipBlanks(const std::string& s, size_t& pos) {
    while (pos < s.size() && (s[pos] == ' ' || s[pos] == '\t')) ++pos;
  }

  YamlNode ParseFlow(const std::string& s, size_t& pos, int no, bool key) {
    std::string tag, anchor;
    ReadProperties(s, pos, no, &tag, &anchor);
    return WithProperties(ParseFlowNode(s, pos, no, key), tag, anchor);
  }

  YamlNode ParseFlowNode(const std::string& s, size_t& pos, int no, bool key) {
    YamlNode node;
    node.line = no;
    if (pos >= s.size()) Fail(no, "missing value in '" + Shown(s) + "'");
    const char c = s[pos];
    if (c == '*') return Alias(s, pos, no);
    if (c == '[' || c == '{') {
      const Nest nest(this, no);
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
        } else if (pos >= s.size()) {
          Fail(no, std::string("missing '") + close + "' in '" + Shown(s) + "'");
        } else if (s[pos] != close) {
          Fail(no, std::string("expected ',' or '") + close + "' in '" + Shown(s) + "'");
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
    if (node.scalar.empty()) Fail(no, "empty value in '" + Shown(s) + "'");
    return node;
  }

  // The nodes of a tree and the characters of its strings.
  static size_t Size(const YamlNode& n) {
    size_t size = 1 + n.tag.size() + n.scalar.size();
    for (const auto& [k, v] : n.map) size += k.size() + Size(v);
    for (const YamlNode& v : n.seq) size += Size(v);
    return size;
  }

  static constexpr int kMaxDepth = 100;
  static constexpr size_t kMaxCopied = 1000000;
  struct Anchor {
    YamlNode node;
    size_t size = 0;  // Size(node)
  };

  std::string file_;
  std::vector<std::string> raw_;  // every line of the text, as written (for block scalars)
  std::vector<Line> lines_;
  std::map<std::string, Anchor> anchors_;
  int depth_ = 0;        // collections being read
  size_t copied_ = 0;    // the Size of what the aliases have copied
};

}  // namespace

YamlNode::YamlNode() = default;
YamlNode::YamlNode(const YamlNode&) = default;
YamlNode::YamlNode(YamlNode&&) noexcept = default;
YamlNode& YamlNode::operator=(const YamlNode&) = default;
YamlNode& YamlNode::operator=(YamlNode&&) noexcept = default;
YamlNode::~YamlNode() = default;

const YamlNode* YamlNode::Find(const std::string& key) const {
  for (const auto& [k, v] : map) {
    if (k == key) return &v;
  }
  return nullptr;
}

YamlNode ParseYamlTree(const std::string& text, const std::string& file, YamlLine* first) {
  if (first) *first = {};
  return TreeParser(text, file, first).Run();
}

}  // namespace lt

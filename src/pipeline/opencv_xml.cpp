// OpenCV FileStorage XML (pipeline/opencv_yaml.h): ParseOpenCvXml reads the
// same entries as the YAML form from <opencv_storage>'s child elements, and
// OpenCvYamlWriter writes them in this form for StorageFormat::kXml.
#include <cctype>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/opencv_yaml.h"

namespace lt {

namespace {

struct XmlElement {
  std::string name;
  int line = 0;
  std::map<std::string, std::string> attributes;
  std::string text;  // character data directly inside (entities decoded)
  std::vector<XmlElement> children;
};

class XmlParser {
 public:
  XmlParser(const std::string& text, std::string file) : s_(text), file_(std::move(file)) {}

  XmlElement Root() {
    SkipMisc();
    if (!Starts("<")) Fail("not an OpenCV FileStorage XML file: expected <opencv_storage>");
    XmlElement root = Element();
    SkipMisc();
    if (pos_ < s_.size()) Fail("unexpected text after </" + root.name + ">");
    if (root.name != "opencv_storage") {
      Fail(root.line, "not an OpenCV FileStorage XML file: the root element is <" + root.name +
                          ">, expected <opencv_storage>");
    }
    return root;
  }

  std::string Where(int line) const { return file_ + ":" + std::to_string(line); }
  [[noreturn]] void Fail(int line, const std::string& message) const { throw InputError(Where(line), message); }

 private:
  [[noreturn]] void Fail(const std::string& message) const { Fail(Line(), message); }
  // The line of pos_, counted on from the last call's (pos_ only moves forward),
  // so an element per line costs the text's length once, not once per element.
  int Line() const {
    for (; line_pos_ < pos_ && line_pos_ < s_.size(); ++line_pos_) line_ += s_[line_pos_] == '\n';
    return line_;
  }
  bool Starts(const char* p) const { return s_.compare(pos_, std::char_traits<char>::length(p), p) == 0; }
  void SkipSpace() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  void SkipPast(const char* end, const char* what) {
    const size_t e = s_.find(end, pos_);
    if (e == std::string::npos) Fail(std::string("unterminated ") + what);
    pos_ = e + std::char_traits<char>::length(end);
  }
  // Declarations, comments and processing instructions between elements.
  void SkipMisc() {
    for (;;) {
      SkipSpace();
      if (Starts("\xEF\xBB\xBF")) {
        pos_ += 3;
      } else if (Starts("<?")) {
        SkipPast("?>", "<?...?>");
      } else if (Starts("<!--")) {
        SkipPast("-->", "comment");
      } else if (Starts("<!")) {
        SkipPast(">", "<!...>");
      } else {
        return;
      }
    }
  }
  std::string Name() {
    const size_t b = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_' ||
                                s_[pos_] == '-' || s_[pos_] == '.' || s_[pos_] == ':')) {
      ++pos_;
    }
    if (pos_ == b) Fail("expected a name");
    return s_.substr(b, pos_ - b);
  }
  std::string Decode(const std::string& t) {
    std::string out;
    for (size_t i = 0; i < t.size(); ++i) {
      if (t[i] != '&') {
        out += t[i];
        continue;
      }
      const size_t semi = t.find(';', i);
      if (semi == std::string::npos) Fail("'&' without ';'");
      const std::string ent = t.substr(i + 1, semi - i - 1);
      if (ent == "lt") out += '<';
      else if (ent == "gt") out += '>';
      else if (ent == "amp") out += '&';
      else if (ent == "quot") out += '"';
      else if (ent == "apos") out += '\'';
      else if (!ent.empty() && ent[0] == '#') out += char(std::strtol(ent.c_str() + (ent[1] == 'x' ? 2 : 1), nullptr, ent[1] == 'x' ? 16 : 10));
      else Fail("unknown entity &" + ent + ";");
      i = semi;
    }
    return out;
  }
  XmlElement Element() {
    XmlElement e;
    e.line = Line();
    if (depth_ == kMaxDepth) Fail("elements nested deeper than " + std::to_string(kMaxDepth) + " levels");
    ++depth_;  // not decremented on an error: the parse ends
    ++pos_;  // '<'
    e.name = Name();
    for (;;) {
      SkipSpace();
      if (Starts("/>")) {
        pos_ += 2;
        --depth_;
        return e;
      }
      if (Starts(">")) {
        ++pos_;
        break;
      }
      const std::string attr = Name();
      SkipSpace();
      if (!Starts("=")) Fail("expected '=' after attribute " + attr);
      ++pos_;
      SkipSpace();
      if (pos_ >= s_.size() || (s_[pos_] != '"' && s_[pos_] != '\'')) Fail("expected a quoted attribute value");
      const char q = s_[pos_++];
      const size_t end = s_.find(q, pos_);
      if (end == std::string::npos) Fail("unterminated attribute value");
      e.attributes[attr] = Decode(s_.substr(pos_, end - pos_));
      pos_ = end + 1;
    }
    for (;;) {
      if (pos_ >= s_.size()) Fail(e.line, "<" + e.name + "> is not closed");
      if (Starts("<!--")) {
        SkipPast("-->", "comment");
      } else if (Starts("</")) {
        pos_ += 2;
        const std::string closing = Name();
        if (closing != e.name) Fail("</" + closing + "> closes <" + e.name + "> (line " + std::to_string(e.line) + ")");
        SkipSpace();
        if (!Starts(">")) Fail("expected '>'");
        ++pos_;
        --depth_;
        return e;
      } else if (Starts("<")) {
        e.children.push_back(Element());
      } else {
        const size_t next = s_.find('<', pos_);
        const size_t end = next == std::string::npos ? s_.size() : next;
        e.text += Decode(s_.substr(pos_, end - pos_));
        pos_ = end;
      }
    }
  }

  static constexpr int kMaxDepth = 100;
  const std::string& s_;
  std::string file_;
  size_t pos_ = 0;
  mutable size_t line_pos_ = 0;  // Line(): the line of s_[line_pos_]
  mutable int line_ = 1;
  int depth_ = 0;  // elements open
};

std::string Trim(const std::string& s) { return std::string(TrimBlanks(s)); }

}  // namespace

std::vector<YamlEntry> ParseOpenCvXml(const std::string& text, const std::string& file) {
  XmlParser parser(text, file);
  const XmlElement root = parser.Root();
  std::vector<YamlEntry> entries;
  std::set<std::string> seen;
  for (const XmlElement& el : root.children) {
    YamlEntry e;
    e.key = el.name;
    e.line = el.line;
    if (!seen.insert(e.key).second) parser.Fail(el.line, "duplicate key '" + e.key + "'");
    const auto type = el.attributes.find("type_id");
    if (type != el.attributes.end() && type->second == "opencv-matrix") {
      e.kind = YamlEntry::Kind::kMatrix;
      std::map<std::string, const XmlElement*> parts;
      for (const XmlElement& c : el.children) {
        if (c.name != "rows" && c.name != "cols" && c.name != "dt" && c.name != "data") {
          parser.Fail(c.line, "unknown matrix element <" + c.name + "> (expected rows, cols, dt, data)");
        }
        parts[c.name] = &c;
      }
      if (parts.size() != 4) parser.Fail(el.line, "matrix '" + e.key + "' needs rows, cols, dt and data");
      auto field = [&](const char* n) { return MatrixField{Trim(parts[n]->text), parser.Where(parts[n]->line)}; };
      const MatrixField data = field("data");
      std::vector<MatrixField> values;
      std::istringstream tokens(data.text);
      for (std::string tok; tokens >> tok;) values.push_back({tok, data.where});
      e.matrix = MakeMatrix(e.key, field("rows"), field("cols"), field("dt"), values, data.where);
    } else if (type != el.attributes.end() || !el.children.empty()) {
      e.kind = YamlEntry::Kind::kOther;  // another type, a sequence or a map: skipped
    } else {
      e.kind = YamlEntry::Kind::kScalar;
      std::string v = Trim(el.text);
      if (v.size() >= 2 && v.front() == '"' && v.back() == '"') {
        v = v.substr(1, v.size() - 2);
        e.quoted = true;
      }
      e.scalar = v;
    }
    entries.push_back(std::move(e));
  }
  return entries;
}

void OpenCvYamlWriter::XmlElement(const std::string& key, const std::string& value) {
  text_ += "<" + key + ">" + value + "</" + key + ">\n";
}

// As cv::FileStorage writes a cv::Mat: the values separated by spaces, four to a line.
void OpenCvYamlWriter::XmlMatrix(const std::string& key, int rows, int cols, const std::vector<double>& data) {
  text_ += "<" + key + " type_id=\"opencv-matrix\">\n  <rows>" + std::to_string(rows) + "</rows>\n  <cols>" +
           std::to_string(cols) + "</cols>\n  <dt>d</dt>\n  <data>";
  for (size_t i = 0; i < data.size(); ++i) text_ += (i % 4 == 0 ? "\n    " : " ") + FormatYamlReal(data[i]);
  text_ += "</data></" + key + ">\n";
}

}  // namespace lt

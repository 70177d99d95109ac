#include "pipeline/opencv_yaml.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <tuple>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "pipeline/yaml_tree.h"

namespace lt {

namespace {

struct Line {
  int no = 0;
  int indent = 0;
  std::string text;  // without indentation and trailing spaces
};

std::string Trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  size_t e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

// Drops a " # comment" from a plain (unquoted) value.
std::string StripComment(const std::string& s) {
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) return Trim(s.substr(0, i));
  }
  return Trim(s);
}

// Parses the whole string as a finite number.
bool ParseReal(const std::string& s, double* v) {
  if (s.empty()) return false;
  const char* begin = s.c_str();
  char* end = nullptr;
  *v = std::strtod(begin, &end);
  return end == begin + s.size() && std::isfinite(*v);
}

// Splits "key: rest" at the first colon followed by a space or the end.
bool SplitKey(const std::string& text, std::string* key, std::string* rest) {
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == ':' && (i + 1 == text.size() || text[i + 1] == ' ' || text[i + 1] == '\t')) {
      *key = Trim(text.substr(0, i));
      *rest = Trim(text.substr(i + 1));
      return !key->empty();
    }
  }
  return false;
}

class Parser {
 public:
  Parser(const std::string& text, std::string file) : file_(std::move(file)) {
    std::istringstream in(text);
    std::string raw;
    int no = 0;
    while (std::getline(in, raw)) {
      ++no;
      if (!raw.empty() && raw.back() == '\r') raw.pop_back();
      size_t indent = 0;
      while (indent < raw.size() && (raw[indent] == ' ' || raw[indent] == '\t')) {
        if (raw[indent] == '\t') Fail(no, "tab in indentation (YAML indents with spaces)");
        ++indent;
      }
      std::string body = Trim(raw.substr(indent));
      if (body.empty() || body[0] == '#') continue;
      lines_.push_back({no, int(indent), body});
    }
  }

  std::vector<YamlEntry> Run() {
    if (lines_.empty() || lines_[0].text.rfind("%YAML", 0) != 0) {
      Fail(lines_.empty() ? 1 : lines_[0].no,
           "not an OpenCV FileStorage YAML file: the first line must be %YAML:1.0 (the XML form starts with <?xml); "
           "nor the camera file of ROS (camera_matrix: {rows, cols, data}), Kalibr (cam0: {intrinsics, ...}) or "
           "camodocal (model_type)");
    }
    std::vector<YamlEntry> entries;
    std::set<std::string> seen;
    size_t i = 1;
    if (i < lines_.size() && lines_[i].indent == 0 && lines_[i].text.rfind("---", 0) == 0) {
      if (Trim(lines_[i].text.substr(3)) != "") Fail(lines_[i].no, "expected '---' alone on its line");
      ++i;
    }
    while (i < lines_.size()) {
      const Line& l = lines_[i];
      if (l.indent == 0 && l.text == "...") break;  // end of document
      if (l.indent != 0) Fail(l.no, "unexpected indentation (expected a top-level 'key: value')");
      if (l.text[0] == '-') Fail(l.no, "top-level sequences are not supported (expected 'key: value')");
      YamlEntry e;
      std::string rest;
      if (!SplitKey(l.text, &e.key, &rest)) Fail(l.no, "expected 'key: value', got '" + l.text + "'");
      if (e.key[0] == '"' || e.key[0] == '\'') Fail(l.no, "quoted keys are not supported");
      e.line = l.no;
      if (!seen.insert(e.key).second) Fail(l.no, "duplicate key '" + e.key + "'");
      // The block: the following indented lines.
      size_t end = i + 1;
      while (end < lines_.size() && lines_[end].indent > 0) ++end;
      ParseValue(rest, i + 1, end, &e);
      entries.push_back(std::move(e));
      i = end;
    }
    return entries;
  }

 private:
  [[noreturn]] void Fail(int line, const std::string& message) const {
    throw InputError(file_ + ":" + std::to_string(line), message);
  }

  void ParseValue(const std::string& rest, size_t begin, size_t end, YamlEntry* e) {
    const int line = e->line;
    if (rest.rfind("!!opencv-matrix", 0) == 0) {
      if (Trim(rest.substr(15)) != "") Fail(line, "'!!opencv-matrix' must be followed by its indented block");
      e->kind = YamlEntry::Kind::kMatrix;
      ParseMatrix(begin, end, e);
      return;
    }
    if (rest.empty() || rest[0] == '!' || rest[0] == '[' || rest[0] == '{' || rest[0] == '&' || rest[0] == '*' ||
        rest[0] == '|' || rest[0] == '>') {
      e->kind = YamlEntry::Kind::kOther;  // a nested structure, tagged node or block scalar: skipped
      return;
    }
    e->kind = YamlEntry::Kind::kScalar;
    if (begin != end) Fail(lines_[begin].no, "unexpected indented line after the scalar value of '" + e->key + "'");
    if (rest[0] == '"' || rest[0] == '\'') {
      const char q = rest[0];
      std::string value;
      size_t k = 1;
      bool closed = false;
      for (; k < rest.size(); ++k) {
        char c = rest[k];
        if (q == '\'' && c == '\'' && k + 1 < rest.size() && rest[k + 1] == '\'') {
          value += '\'';
          ++k;
        } else if (q == '"' && c == '\\' && k + 1 < rest.size()) {
          char n = rest[++k];
          value += n == 'n' ? '\n' : n == 't' ? '\t' : n;
        } else if (c == q) {
          closed = true;
          break;
        } else {
          value += c;
        }
      }
      if (!closed) Fail(line, "unterminated quoted string");
      std::string after = Trim(rest.substr(k + 1));
      if (!after.empty() && after[0] != '#') Fail(line, "unexpected text after the quoted string: '" + after + "'");
      e->scalar = value;
      e->quoted = true;
      return;
    }
    e->scalar = StripComment(rest);
  }

  void ParseMatrix(size_t begin, size_t end, YamlEntry* e) {
    YamlMatrix& m = e->matrix;
    bool has_rows = false, has_cols = false, has_dt = false, has_data = false;
    std::string data;
    int data_line = e->line;
    for (size_t i = begin; i < end; ++i) {
      const Line& l = lines_[i];
      std::string key, rest;
      if (!SplitKey(l.text, &key, &rest)) Fail(l.no, "expected 'rows:', 'cols:', 'dt:' or 'data:' in the matrix");
      auto integer = [&](int* out) {
        std::string s = StripComment(rest);
        char* stop = nullptr;
        long v = std::strtol(s.c_str(), &stop, 10);
        if (s.empty() || *stop != '\0' || v < 1 || v > 100000000) {
          Fail(l.no, key + " must be a positive integer, got '" + s + "'");
        }
        *out = int(v);
      };
      if (key == "rows") {
        integer(&m.rows);
        has_rows = true;
      } else if (key == "cols") {
        integer(&m.cols);
        has_cols = true;
      } else if (key == "dt") {
        const std::string dt = StripComment(rest);
        if (!ParseMatrixDt(dt, &m)) {
          Fail(l.no, "dt must be d, f, i, u, s, w or c, with an optional channel count of 1 to 4 (2f), got '" + dt + "'");
        }
        has_dt = true;
      } else if (key == "data") {
        has_data = true;
        data_line = l.no;
        data = rest;
        // The sequence may continue on the following lines until its ']'.
        while (data.find(']') == std::string::npos && i + 1 < end) data += " " + lines_[++i].text;
      } else {
        Fail(l.no, "unknown matrix key '" + key + "' (expected rows, cols, dt, data)");
      }
    }
    if (!has_rows || !has_cols || !has_dt || !has_data) {
      Fail(e->line, "matrix '" + e->key + "' needs rows, cols, dt and data");
    }
    std::string s = Trim(data);
    if (s.empty() || s.front() != '[') Fail(data_line, "data must be a sequence [ v0, v1, ... ]");
    size_t close = s.find(']');
    if (close == std::string::npos) Fail(data_line, "data: missing ']'");
    std::string after = Trim(s.substr(close + 1));
    if (!after.empty() && after[0] != '#') Fail(data_line, "unexpected text after data: '" + after + "'");
    std::string inner = Trim(s.substr(1, close - 1));
    if (!inner.empty()) {
      std::stringstream ss(inner);
      for (std::string tok; std::getline(ss, tok, ',');) {
        tok = Trim(tok);
        double v = 0;
        if (!ParseReal(tok, &v)) Fail(data_line, "data value " + std::to_string(m.data.size()) + " is not a finite number: '" + tok + "'");
        m.data.push_back(v);
      }
    }
    const size_t expected = size_t(m.rows) * size_t(m.cols) * size_t(m.channels);
    if (m.data.size() != expected) {
      Fail(data_line, "matrix '" + e->key + "' is " + std::to_string(m.rows) + "x" + std::to_string(m.cols) +
                          (m.channels > 1 ? " of " + std::to_string(m.channels) + " channels" : std::string()) +
                          " and needs " + std::to_string(expected) + " values, got " + std::to_string(m.data.size()));
    }
  }

  std::string file_;
  std::vector<Line> lines_;
};

// A node's text as the file holds it (a quoted scalar in its quotes, so that
// it is no number; "" for a collection or nothing), for the matrix's checks.
MatrixField Field(const YamlNode& n, const std::string& file) {
  const std::string text = n.kind != YamlNode::Kind::kScalar ? "" : n.quoted ? "\"" + n.scalar + "\"" : n.scalar;
  return {text, file + ":" + std::to_string(n.line)};
}

// The matrix of an "!!opencv-matrix" node: a mapping of rows, cols, dt and data.
YamlMatrix ReadMatrix(const std::string& key, const YamlNode& n, const std::string& file) {
  const std::string where = file + ":" + std::to_string(n.line);
  if (n.kind != YamlNode::Kind::kMap && n.kind != YamlNode::Kind::kNull) {
    throw InputError(where, "'!!opencv-matrix' must be followed by its indented block (rows, cols, dt, data)");
  }
  for (const auto& [k, v] : n.map) {
    if (k != "rows" && k != "cols" && k != "dt" && k != "data") {
      throw InputError(file + ":" + std::to_string(v.line), "unknown matrix key '" + k + "' (expected rows, cols, dt, data)");
    }
  }
  const YamlNode *rows = n.Find("rows"), *cols = n.Find("cols"), *dt = n.Find("dt"), *data = n.Find("data");
  if (!rows || !cols || !dt || !data) throw InputError(where, "matrix '" + key + "' needs rows, cols, dt and data");
  const MatrixField data_field = Field(*data, file);
  if (data->kind != YamlNode::Kind::kSeq) throw InputError(data_field.where, "data must be a sequence [ v0, v1, ... ]");
  std::vector<MatrixField> values;
  for (const YamlNode& v : data->seq) values.push_back(Field(v, file));
  return MakeMatrix(key, Field(*rows, file), Field(*cols, file), Field(*dt, file), values, data_field.where);
}

}  // namespace

YamlMatrix MakeMatrix(const std::string& key, const MatrixField& rows, const MatrixField& cols, const MatrixField& dt,
                      const std::vector<MatrixField>& data, const std::string& data_where) {
  YamlMatrix m;
  for (auto [name, field, out] : {std::tuple{"rows", &rows, &m.rows}, std::tuple{"cols", &cols, &m.cols}}) {
    char* stop = nullptr;
    const long v = std::strtol(field->text.c_str(), &stop, 10);
    if (field->text.empty() || *stop != '\0' || v < 1 || v > 100000000) {
      throw InputError(field->where, std::string(name) + " must be a positive integer, got '" + field->text + "'");
    }
    *out = int(v);
  }
  if (!ParseMatrixDt(dt.text, &m)) {
    throw InputError(dt.where, "dt must be d, f, i, u, s, w or c, with an optional channel count of 1 to 4 (2f), got '" +
                                   dt.text + "'");
  }
  for (const MatrixField& value : data) {
    double v = 0;
    if (!ParseReal(value.text, &v)) {
      throw InputError(value.where, "data value " + std::to_string(m.data.size()) + " is not a finite number: '" +
                                        value.text + "'");
    }
    m.data.push_back(v);
  }
  const size_t expected = size_t(m.rows) * size_t(m.cols) * size_t(m.channels);
  if (m.data.size() != expected) {
    throw InputError(data_where, "matrix '" + key + "' is " + std::to_string(m.rows) + "x" + std::to_string(m.cols) +
                                     (m.channels > 1 ? " of " + std::to_string(m.channels) + " channels" : std::string()) +
                                     " and needs " + std::to_string(expected) + " values, got " +
                                     std::to_string(m.data.size()));
  }
  return m;
}

std::vector<YamlEntry> ParseOpenCvYaml(const std::string& text, const std::string& file) {
  YamlLine first;
  const YamlNode root = ParseYamlTree(text, file, &first);
  if (first.text.rfind("%YAML", 0) != 0) {
    throw InputError(file + ":" + std::to_string(first.no),
                     "not an OpenCV FileStorage YAML file: the first line must be %YAML:1.0 (the XML form starts with "
                     "<?xml); nor the camera file of ROS (camera_matrix: {rows, cols, data}), Kalibr (cam0: "
                     "{intrinsics, ...}) or camodocal (model_type)");
  }
  std::vector<YamlEntry> entries;
  for (const auto& [key, node] : root.map) {
    YamlEntry e;
    e.key = key;
    e.line = node.line;
    if (node.tag == "!!opencv-matrix") {
      e.kind = YamlEntry::Kind::kMatrix;
      e.matrix = ReadMatrix(key, node, file);
    } else if (node.kind == YamlNode::Kind::kScalar && node.tag.empty()) {
      e.scalar = node.scalar;
      e.quoted = node.quoted;
    } else {
      e.kind = YamlEntry::Kind::kOther;  // a collection, nothing, or another type: skipped
    }
    entries.push_back(std::move(e));
  }
  return entries;
}

bool IsOpenCvXmlText(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  return (first != std::string::npos && text[first] == '<') || (bom && text.size() > 3 && text[3] == '<');
}

OpenCvYaml OpenCvYaml::Parse(const std::string& text, const std::string& file) {
  OpenCvYaml y;
  y.file_ = file;
  if (IsOpenCvXmlText(text)) {
    y.entries_ = ParseOpenCvXml(text, file);
  } else {
    y.entries_ = ParseOpenCvYaml(text, file);
  }
  return y;
}

std::string OpenCvYaml::ReadText(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path)) throw InputError(path.string(), "is a folder, not a calibration file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path.string(), "cannot read file");
  return ss.str();
}

OpenCvYaml OpenCvYaml::Read(const std::filesystem::path& path) { return Parse(ReadText(path), path.string()); }

const YamlEntry* OpenCvYaml::Find(const std::string& key) const {
  for (const auto& e : entries_) {
    if (e.key == key) return &e;
  }
  return nullptr;
}

double OpenCvYaml::Number(const YamlEntry& e) const {
  double v = 0;
  if (e.kind != YamlEntry::Kind::kScalar || e.quoted || !ParseReal(e.scalar, &v)) {
    throw InputError(Where(e), e.key + " must be a finite number" +
                                   (e.kind == YamlEntry::Kind::kScalar ? ", got '" + e.scalar + "'" : ""));
  }
  return v;
}

long long OpenCvYaml::Integer(const YamlEntry& e, long long lo, long long hi) const {
  const std::string& s = e.scalar;
  char* stop = nullptr;
  long long v = e.kind == YamlEntry::Kind::kScalar && !e.quoted && !s.empty() ? std::strtoll(s.c_str(), &stop, 10) : 0;
  if (e.kind != YamlEntry::Kind::kScalar || e.quoted || s.empty() || *stop != '\0' || v < lo || v > hi) {
    throw InputError(Where(e), e.key + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                   "]" + (e.kind == YamlEntry::Kind::kScalar ? ", got '" + s + "'" : ""));
  }
  return v;
}

std::string OpenCvYaml::String(const YamlEntry& e) const {
  if (e.kind != YamlEntry::Kind::kScalar) throw InputError(Where(e), e.key + " must be a string");
  return e.scalar;
}

const YamlMatrix& OpenCvYaml::Matrix(const YamlEntry& e) const {
  if (e.kind != YamlEntry::Kind::kMatrix) throw InputError(Where(e), e.key + " must be an !!opencv-matrix");
  if (e.matrix.channels != 1) {
    throw InputError(Where(e), e.key + " must have one channel (dt d), got " + std::to_string(e.matrix.channels) +
                                   " (dt " + std::to_string(e.matrix.channels) + e.matrix.dt + ")");
  }
  return e.matrix;
}

bool ParseMatrixDt(std::string dt, YamlMatrix* m) {
  dt = Trim(dt);
  if (dt.size() >= 2 && (dt.front() == '"' || dt.front() == '\'') && dt.back() == dt.front()) {
    dt = dt.substr(1, dt.size() - 2);
  }
  int channels = 1;
  if (dt.size() == 2 && dt[0] >= '1' && dt[0] <= '4') {
    channels = dt[0] - '0';
    dt = dt.substr(1);
  }
  if (dt.size() != 1 || std::string("dfiuswc").find(dt[0]) == std::string::npos) return false;
  m->dt = dt;
  m->channels = channels;
  return true;
}

std::string FormatYamlReal(double v) {
  std::string s = FormatNumber(v);
  if (!std::isfinite(v)) return v != v ? ".Nan" : (v > 0 ? ".Inf" : "-.Inf");
  if (s.find_first_of(".e") == std::string::npos) s += ".";
  return s;
}

OpenCvYamlWriter::OpenCvYamlWriter(StorageFormat format)
    : format_(format),
      text_(format == StorageFormat::kXml ? "<?xml version=\"1.0\"?>\n<opencv_storage>\n" : "%YAML:1.0\n---\n") {}

std::string OpenCvYamlWriter::text() const {
  return format_ == StorageFormat::kXml ? text_ + "</opencv_storage>\n" : text_;
}

void OpenCvYamlWriter::Integer(const std::string& key, long long value) {
  if (format_ == StorageFormat::kXml) return XmlElement(key, std::to_string(value));
  text_ += key + ": " + std::to_string(value) + "\n";
}

void OpenCvYamlWriter::Number(const std::string& key, double value) {
  if (!std::isfinite(value)) throw std::invalid_argument("OpenCvYamlWriter: " + key + " is not finite");
  if (format_ == StorageFormat::kXml) return XmlElement(key, FormatYamlReal(value));
  text_ += key + ": " + FormatYamlReal(value) + "\n";
}

void OpenCvYamlWriter::String(const std::string& key, const std::string& value) {
  bool plain = !value.empty();
  for (char c : value) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) plain = false;
  }
  double ignored = 0;
  if (plain && !ParseReal(value, &ignored)) {
    if (format_ == StorageFormat::kXml) return XmlElement(key, value);
    text_ += key + ": " + value + "\n";
    return;
  }
  std::string q = "\"";
  for (char c : value) {
    if (format_ == StorageFormat::kXml) {
      // OpenCV's entities; the surrounding quotes mark a string.
      switch (c) {
        case '<': q += "&lt;"; continue;
        case '>': q += "&gt;"; continue;
        case '&': q += "&amp;"; continue;
        case '"': q += "&quot;"; continue;
        case '\'': q += "&apos;"; continue;
        case '\n': q += "&#xa;"; continue;
        default: q += c; continue;
      }
    }
    if (c == '"' || c == '\\') q += '\\';
    if (c == '\n') {
      q += "\\n";
      continue;
    }
    q += c;
  }
  q += '"';
  if (format_ == StorageFormat::kXml) return XmlElement(key, q);
  text_ += key + ": " + q + "\n";
}

void OpenCvYamlWriter::Matrix(const std::string& key, int rows, int cols, const std::vector<double>& data) {
  if (rows < 1 || cols < 1 || data.size() != size_t(rows) * size_t(cols)) {
    throw std::invalid_argument("OpenCvYamlWriter: " + key + ": data size does not match rows x cols");
  }
  for (double v : data) {
    if (!std::isfinite(v)) throw std::invalid_argument("OpenCvYamlWriter: " + key + " holds a non-finite value");
  }
  if (format_ == StorageFormat::kXml) return XmlMatrix(key, rows, cols, data);
  text_ += key + ": !!opencv-matrix\n   rows: " + std::to_string(rows) + "\n   cols: " + std::to_string(cols) +
           "\n   dt: d\n   data: [ ";
  for (size_t i = 0; i < data.size(); ++i) {
    if (i > 0) text_ += (i % 4 == 0) ? ",\n       " : ", ";
    text_ += FormatYamlReal(data[i]);
  }
  text_ += " ]\n";
}

}  // namespace lt

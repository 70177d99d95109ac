#include "pipeline/opencv_yaml.h"

#include <cctype>
#include <cmath>
#include <stdexcept>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/yaml_tree.h"

namespace lt {

namespace {

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
      throw InputError(file + ":" + std::to_string(v.line),
                       "unknown matrix key '" + k + "' (expected rows, cols, dt, data)");
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
  // A field's text is as the file holds it (a quoted value in its quotes, so no number).
  auto value = [](const MatrixField& f, const std::string& name) { return YamlValue{&f.text, false, name, f.where}; };
  m.rows = int(YamlInteger(value(rows, "rows"), 1, 100000000));
  m.cols = int(YamlInteger(value(cols, "cols"), 1, 100000000));
  m.dt = std::string(TrimBlanks(dt.text));
  if (m.dt.size() >= 2 && (m.dt[0] == '"' || m.dt[0] == '\'') && m.dt.back() == m.dt[0]) {
    m.dt = m.dt.substr(1, m.dt.size() - 2);
  }
  if (m.dt.size() == 2 && m.dt[0] >= '1' && m.dt[0] <= '4') {
    m.channels = m.dt[0] - '0';
    m.dt = m.dt.substr(1);
  }
  if (m.dt.size() != 1 || std::string("dfiuswc").find(m.dt[0]) == std::string::npos) {
    throw InputError(dt.where, "dt must be d, f, i, u, s, w or c, with an optional channel count of 1 to 4 (2f), "
                               "got '" + dt.text + "'");
  }
  for (const MatrixField& v : data) m.data.push_back(YamlNumber(value(v, "data value " + std::to_string(m.data.size()))));
  const size_t expected = size_t(m.rows) * size_t(m.cols) * size_t(m.channels);
  if (m.data.size() != expected) {
    const std::string of = m.channels > 1 ? " of " + std::to_string(m.channels) + " channels" : "";
    throw InputError(data_where, "matrix '" + key + "' is " + std::to_string(m.rows) + "x" + std::to_string(m.cols) +
                                     of + " and needs " + std::to_string(expected) + " values, got " +
                                     std::to_string(m.data.size()));
  }
  return m;
}

namespace {

// The entries of a FileStorage YAML text's tree, whose first line is a %YAML directive.
std::vector<YamlEntry> OpenCvYamlEntries(const YamlNode& root, const YamlLine& first, const std::string& file) {
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

}  // namespace

bool IsOpenCvXmlText(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  return (first != std::string::npos && text[first] == '<') || (bom && text.size() > 3 && text[3] == '<');
}

OpenCvYaml OpenCvYaml::Parse(const std::string& text, const std::string& file) {
  if (!IsOpenCvXmlText(text)) {
    YamlLine first;
    const YamlNode root = ParseYamlTree(text, file, &first);
    return Parse(root, first, file);
  }
  OpenCvYaml y;
  y.file_ = file;
  y.entries_ = ParseOpenCvXml(text, file);
  return y;
}

OpenCvYaml OpenCvYaml::Parse(const YamlNode& root, const YamlLine& first, const std::string& file) {
  OpenCvYaml y;
  y.file_ = file;
  y.entries_ = OpenCvYamlEntries(root, first, file);
  return y;
}

std::string OpenCvYaml::ReadText(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path)) throw InputError(path.string(), "is a folder, not a calibration file");
  return ReadTextFile(path, path.string());
}

OpenCvYaml OpenCvYaml::Read(const std::filesystem::path& path) { return Parse(ReadText(path), path.string()); }

const YamlEntry* OpenCvYaml::Find(const std::string& key) const {
  for (const auto& e : entries_) {
    if (e.key == key) return &e;
  }
  return nullptr;
}

YamlValue OpenCvYaml::Value(const YamlEntry& e) const {
  return {e.kind == YamlEntry::Kind::kScalar ? &e.scalar : nullptr, e.quoted, e.key, Where(e)};
}

double OpenCvYaml::Number(const YamlEntry& e) const { return YamlNumber(Value(e)); }

long long OpenCvYaml::Integer(const YamlEntry& e, long long lo, long long hi) const {
  return YamlInteger(Value(e), lo, hi);
}

std::string OpenCvYaml::String(const YamlEntry& e) const { return YamlString(Value(e)); }

const YamlMatrix& OpenCvYaml::Matrix(const YamlEntry& e) const {
  if (e.kind != YamlEntry::Kind::kMatrix) throw InputError(Where(e), e.key + " must be an !!opencv-matrix");
  if (e.matrix.channels != 1) {
    throw InputError(Where(e), e.key + " must have one channel (dt d), got " + std::to_string(e.matrix.channels) +
                                   " (dt " + std::to_string(e.matrix.channels) + e.matrix.dt + ")");
  }
  return e.matrix;
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
  if (plain && !ParseYamlReal(value, &ignored)) {
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

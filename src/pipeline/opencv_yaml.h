// The subset of OpenCV's FileStorage YAML format that calibration files use
// (docs/pipeline.md, "Calibration file"): a "%YAML:1.0" header line, an
// optional "---", then top-level entries
//
//   key: scalar                      number or string (plain, "double" or 'single' quoted)
//   key: !!opencv-matrix             a matrix: the indented block (or a flow map { rows: R, ... })
//      rows: R                       R >= 1
//      cols: C                       C >= 1
//      dt: d                         d, f (floating), i, u, s, w, c (integer), with an optional
//                                    channel count ("2f": 2 values per element; the sample's image points)
//      data: [ v0, v1, ... ]         R x C values, row-major; may span lines (or a block sequence)
//
// The text is read by the YAML tree (pipeline/yaml_tree.h: comments, quoting,
// flow and block collections, block scalars, anchors); its top-level entries
// are these. Other top-level values (nested mappings, sequences, other tags)
// are skipped as "other", so a file written by OpenCV's calibration samples
// with extra entries still reads; the consumer decides what to do with keys it
// does not know. Errors are lt::InputError naming "file:line".
//
// OpenCV's XML form (cv::FileStorage to a .xml file) reads into the same
// entries: "<?xml ...?>", then <opencv_storage> whose child elements are the
// top-level keys: <key>scalar</key> (a "quoted" string or a number), a matrix
// <key type_id="opencv-matrix"> with <rows>, <cols>, <dt> and <data> (values
// separated by white space); other types and nested elements are "other".
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/yaml_scalar.h"

namespace lt {

struct YamlNode;  // pipeline/yaml_tree.h
struct YamlLine;

struct YamlMatrix {
  int rows = 0, cols = 0;
  int channels = 1;          // dt "2f": 2 (OpenCV's sample writes its image points so)
  std::string dt = "d";      // the element type without the channel count
  std::vector<double> data;  // row-major, channels interleaved, finite
  double At(int r, int c) const { return data[size_t(r) * size_t(cols) + size_t(c)]; }
};

struct YamlEntry {
  enum class Kind { kScalar, kMatrix, kOther };
  std::string key;
  int line = 0;  // 1-based line of the key
  Kind kind = Kind::kScalar;
  std::string scalar;  // kScalar: the value, unquoted
  bool quoted = false;  // kScalar: the value was quoted (a string, not a number)
  YamlMatrix matrix;   // kMatrix
};

class OpenCvYaml {
 public:
  // Parses text; `file` names it in errors.
  static OpenCvYaml Parse(const std::string& text, const std::string& file);
  // The YAML form from its tree (ParseYamlTree of the text, `first` its first
  // line, which must be the %YAML directive), so a caller that has parsed the
  // text does not parse it again.
  static OpenCvYaml Parse(const YamlNode& root, const YamlLine& first, const std::string& file);
  static OpenCvYaml Read(const std::filesystem::path& path);  // errors name the path
  // The whole text of a file (lt::InputError naming the path when it cannot be read).
  static std::string ReadText(const std::filesystem::path& path);

  const std::string& file() const { return file_; }
  const std::vector<YamlEntry>& entries() const { return entries_; }
  const YamlEntry* Find(const std::string& key) const;
  // "file:line" of an entry, for errors.
  std::string Where(const YamlEntry& e) const { return file_ + ":" + std::to_string(e.line); }

  // Typed access; each throws lt::InputError at the entry's line when the
  // value has the wrong kind or range.
  double Number(const YamlEntry& e) const;
  long long Integer(const YamlEntry& e, long long lo, long long hi) const;
  std::string String(const YamlEntry& e) const;
  const YamlMatrix& Matrix(const YamlEntry& e) const;
  // An entry as a value for the typed reads (pipeline/yaml_scalar.h), named by its key.
  YamlValue Value(const YamlEntry& e) const;

 private:
  std::string file_;
  std::vector<YamlEntry> entries_;
};

// Whether a text is the XML form (starts with '<', after blanks or a BOM).
bool IsOpenCvXmlText(const std::string& text);
// The entries of an OpenCV FileStorage XML text (OpenCvYaml::Parse calls it for
// a text that starts with '<').
std::vector<YamlEntry> ParseOpenCvXml(const std::string& text, const std::string& file);

// A matrix field as either form holds it: its text and its place ("file:line").
struct MatrixField {
  std::string text, where;
};
// The matrix `key` from its fields, in either form: rows and cols positive
// integers, dt one of OpenCV's ("d", "2f": 1 to 4 channels of d f i u s w c;
// quoted or not), the data values finite numbers, rows x cols x channels of
// them. Errors are lt::InputError at the field's place (the count: data_where).
YamlMatrix MakeMatrix(const std::string& key, const MatrixField& rows, const MatrixField& cols, const MatrixField& dt,
                      const std::vector<MatrixField>& data, const std::string& data_where);

// The two text forms of cv::FileStorage.
enum class StorageFormat { kYaml, kXml };

// Writes the same subset, formatted as OpenCV writes it (numbers round-trip
// exactly): YAML ("%YAML:1.0", "key: value", "!!opencv-matrix"), or XML
// ("<?xml version=\"1.0\"?>", <opencv_storage>, <key>value</key>, a matrix as
// <key type_id="opencv-matrix"> with <rows>, <cols>, <dt>, <data>).
class OpenCvYamlWriter {
 public:
  explicit OpenCvYamlWriter(StorageFormat format = StorageFormat::kYaml);
  void Integer(const std::string& key, long long value);
  void Number(const std::string& key, double value);
  void String(const std::string& key, const std::string& value);
  // rows x cols values, row-major, dt "d".
  void Matrix(const std::string& key, int rows, int cols, const std::vector<double>& data);
  // The whole text (XML: with the closing </opencv_storage>).
  std::string text() const;

 private:
  // XML forms, in opencv_xml.cpp: <key>value</key> (value already escaped) and a matrix.
  void XmlElement(const std::string& key, const std::string& value);
  void XmlMatrix(const std::string& key, int rows, int cols, const std::vector<double>& data);

  StorageFormat format_;
  std::string text_;
};

// A number as OpenCV writes reals: shortest round-trip form, with a decimal
// point ("1." rather than "1") so it reads back as a real.
std::string FormatYamlReal(double v);

}  // namespace lt

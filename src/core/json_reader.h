// Strict reading of JSON configuration files (scene files, calibration files).
//
// Every accessor knows where it is: a Value carries the file name and the JSON
// pointer of its node, so any error names both ("scene.json: /sensor/camera/
// f_number: must be > 0, got 0"). An Object remembers which keys were read;
// Finish() rejects the first key nobody asked for, so typos never pass silently.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace lt::json {

// An allowed interval for a number, with open or closed ends.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_closed = true;
  bool hi_closed = true;

  static Range Any() { return {}; }
  static Range Positive() { return {0.0, Range{}.hi, false, true}; }     // > 0
  static Range NonNegative() { return {0.0, Range{}.hi, true, true}; }  // >= 0
  static Range AtLeast(double lo) { return {lo, Range{}.hi, true, true}; }
  static Range Greater(double lo) { return {lo, Range{}.hi, false, true}; }
  static Range Closed(double lo, double hi) { return {lo, hi, true, true}; }
  static Range OpenClosed(double lo, double hi) { return {lo, hi, false, true}; }
  static Range ClosedOpen(double lo, double hi) { return {lo, hi, true, false}; }
  static Range Open(double lo, double hi) { return {lo, hi, false, false}; }

  bool Contains(double v) const;
  // "must be > 0", "must be in [0, 1]", ...
  std::string Describe() const;
};

struct Context;

class Object;

// A node of a parsed document, with its file and JSON pointer.
class Value {
 public:
  Value(std::shared_ptr<const Context> ctx, const nlohmann::json* node, std::string pointer);

  const nlohmann::json& raw() const { return *node_; }
  const std::string& pointer() const { return pointer_; }
  const std::string& file() const;
  // "scene.json: /sensor/camera" (the `where` of an error at this node).
  std::string where() const;
  [[noreturn]] void Fail(const std::string& message) const;

  bool IsObject() const { return node_->is_object(); }
  bool IsArray() const { return node_->is_array(); }
  bool IsString() const { return node_->is_string(); }
  bool IsNumber() const { return node_->is_number(); }

  double Number(Range range = Range::Any()) const;  // finite, within range
  int64_t Integer(Range range = Range::Any()) const;
  bool Bool() const;
  std::string String() const;
  std::string Enum(std::initializer_list<std::string_view> choices) const;
  std::vector<Value> Array(size_t min_size = 0, size_t max_size = SIZE_MAX) const;
  std::vector<double> Numbers(size_t size, Range range = Range::Any()) const;
  Eigen::Vector3d Vec3(Range range = Range::Any()) const;
  // A path, resolved against the folder of the file this value came from.
  std::filesystem::path Path() const;
  // Path() of a file that must exist, as FindExportedFile finds it (a path
  // written on Windows: backslashes, another letter case); fails "<what> not
  // found (looked for ...)".
  std::filesystem::path ExistingFile(std::string_view what) const;
  Object AsObject() const;

  Value Child(std::string_view key) const;  // node must be an object holding key
  Value Child(size_t index) const;          // node must be an array

 private:
  std::shared_ptr<const Context> ctx_;
  const nlohmann::json* node_;
  std::string pointer_;
};

// An object whose keys are checked: each getter marks its key as known, and
// Finish() fails on the first key that no getter asked for.
class Object {
 public:
  explicit Object(const Value& v);  // fails unless v is an object

  const Value& value() const { return v_; }
  [[noreturn]] void Fail(const std::string& message) const { v_.Fail(message); }

  bool Has(std::string_view key) const;  // marks key as known
  Value Get(std::string_view key) const;  // required
  std::optional<Value> Find(std::string_view key) const;
  Object GetObject(std::string_view key) const;  // required object
  std::optional<Object> FindObject(std::string_view key) const;

  double Number(std::string_view key, Range range = Range::Any()) const;
  double Number(std::string_view key, double fallback, Range range = Range::Any()) const;
  int64_t Integer(std::string_view key, Range range = Range::Any()) const;
  int64_t Integer(std::string_view key, int64_t fallback, Range range = Range::Any()) const;
  bool Bool(std::string_view key, bool fallback) const;
  std::string String(std::string_view key) const;
  std::string String(std::string_view key, const std::string& fallback) const;
  std::string Enum(std::string_view key, std::initializer_list<std::string_view> choices) const;
  std::string Enum(std::string_view key, std::string_view fallback,
                   std::initializer_list<std::string_view> choices) const;
  Eigen::Vector3d Vec3(std::string_view key, Range range = Range::Any()) const;
  Eigen::Vector3d Vec3(std::string_view key, const Eigen::Vector3d& fallback,
                       Range range = Range::Any()) const;
  std::filesystem::path Path(std::string_view key) const;

  // Marks keys as known without reading them (for sections read elsewhere).
  void Accept(std::initializer_list<std::string_view> keys) const;
  // Throws on the first key (in document order) that was never asked for.
  void Finish() const;

 private:
  Value v_;
  mutable std::set<std::string, std::less<>> known_;
};

// A parsed file. Values made from it keep it alive.
class Document {
 public:
  Value Root() const;
  const std::string& file() const;

  // Reads and parses a JSON file. `display_name` is how errors name it
  // (default: the path as given). Syntax errors name file:line:column.
  static Document Load(const std::filesystem::path& path, std::string display_name = "");
  // Parses text held in memory; relative paths resolve against base_dir.
  static Document Parse(const std::string& text, std::string display_name,
                        const std::filesystem::path& base_dir);

 private:
  std::shared_ptr<const Context> ctx_;
};

// Escapes a key for use in a JSON pointer (RFC 6901: "~" -> "~0", "/" -> "~1").
std::string EscapePointerToken(std::string_view key);

}  // namespace lt::json

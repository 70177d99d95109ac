// Value and Object (core/json_reader.h): typed, range-checked access to a parsed JSON
// document's nodes with their file and JSON pointer. Document (parsing, loading) is in
// json_document.cpp.
#include "core/json_reader.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <vector>

#include "core/error.h"
#include "core/file_lookup.h"
#include "core/json_context.h"

namespace lt::json {

namespace {

const char* TypeName(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return "null";
    case nlohmann::json::value_t::boolean: return "a boolean";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
    case nlohmann::json::value_t::number_float: return "a number";
    case nlohmann::json::value_t::string: return "a string";
    case nlohmann::json::value_t::array: return "an array";
    case nlohmann::json::value_t::object: return "an object";
    default: return "an unsupported value";
  }
}

// Edits (insert, delete, replace, swap two neighbours) from a to b, letter case ignored.
size_t TypoDistance(std::string_view a, std::string_view b) {
  auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; };
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1])) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

// The key of `object` that a missing required `key` was most likely written as: a
// key no getter asked for that is a typo of it ("exposre_us", "power_mW": one edit,
// two from 8 letters on) or it without its unit suffix ("power" for "power_mw").
// Empty if none; short keys ("fx") get no guess.
std::string MisspeltKey(const nlohmann::json& object, std::string_view key,
                        const std::set<std::string, std::less<>>& known) {
  if (key.size() < 4) return "";
  const size_t max_edits = key.size() >= 8 ? 2 : 1;
  std::string best;
  size_t best_score = SIZE_MAX;
  for (auto it = object.begin(); it != object.end(); ++it) {
    const std::string& k = it.key();
    if (known.count(k) || k.empty()) continue;
    const bool without_unit = k.size() >= 3 && key.size() > k.size() && key.substr(0, k.size()) == k && key[k.size()] == '_';
    const size_t edits = TypoDistance(k, key);
    const size_t score = edits <= max_edits ? edits : without_unit ? max_edits + 1 : SIZE_MAX;
    if (score < best_score) best = k, best_score = score;
  }
  return best;
}

}  // namespace

bool Range::Contains(double v) const {
  if (std::isnan(v)) return false;
  bool above = lo_closed ? v >= lo : v > lo;
  bool below = hi_closed ? v <= hi : v < hi;
  return above && below;
}

std::string Range::Describe() const {
  bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    return "must be in " + std::string(lo_closed ? "[" : "(") + FormatNumber(lo) + ", " +
           FormatNumber(hi) + (hi_closed ? "]" : ")");
  }
  if (has_lo) return std::string("must be ") + (lo_closed ? ">= " : "> ") + FormatNumber(lo);
  if (has_hi) return std::string("must be ") + (hi_closed ? "<= " : "< ") + FormatNumber(hi);
  return "must be finite";
}

std::string EscapePointerToken(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

// ---------------------------------------------------------------- Value

Value::Value(std::shared_ptr<const Context> ctx, const nlohmann::json* node, std::string pointer)
    : ctx_(std::move(ctx)), node_(node), pointer_(std::move(pointer)) {}

const std::string& Value::file() const { return ctx_->file; }

std::string Value::where() const { return ctx_->file + ": " + (pointer_.empty() ? "/" : pointer_); }

void Value::Fail(const std::string& message) const { throw InputError(where(), message); }

double Value::Number(Range range) const {
  if (!node_->is_number()) Fail(std::string("must be a number, got ") + TypeName(*node_));
  double v = node_->get<double>();
  if (!std::isfinite(v)) Fail("must be finite, got " + FormatNumber(v));
  if (!range.Contains(v)) Fail(range.Describe() + ", got " + FormatNumber(v));
  return v;
}

int64_t Value::Integer(Range range) const {
  if (node_->is_number_integer()) {
    if (node_->is_number_unsigned() && node_->get<uint64_t>() > uint64_t(INT64_MAX)) {
      Fail("integer is too large");
    }
    int64_t v = node_->get<int64_t>();
    if (!range.Contains(double(v))) Fail(range.Describe() + ", got " + std::to_string(v));
    return v;
  }
  if (node_->is_number()) {
    // 2.0 is an integer, as JSON Schema counts it; 2.5 is not.
    const double d = node_->get<double>();
    if (std::isfinite(d) && d == std::floor(d) && std::abs(d) <= 9007199254740992.0) {
      const int64_t v = int64_t(d);
      if (!range.Contains(d)) Fail(range.Describe() + ", got " + std::to_string(v));
      return v;
    }
    Fail("must be an integer, got " + FormatNumber(d));
  }
  Fail(std::string("must be an integer, got ") + TypeName(*node_));
}

bool Value::Bool() const {
  if (!node_->is_boolean()) Fail(std::string("must be true or false, got ") + TypeName(*node_));
  return node_->get<bool>();
}

std::string Value::String() const {
  if (!node_->is_string()) Fail(std::string("must be a string, got ") + TypeName(*node_));
  return node_->get<std::string>();
}

std::string Value::Enum(std::initializer_list<std::string_view> choices) const {
  std::string s = String();
  std::string list;
  for (auto c : choices) {
    if (s == c) return s;
    list += (list.empty() ? "" : ", ") + std::string("\"") + std::string(c) + "\"";
  }
  Fail("must be one of " + list + ", got \"" + s + "\"");
}

std::vector<Value> Value::Array(size_t min_size, size_t max_size) const {
  if (!node_->is_array()) Fail(std::string("must be an array, got ") + TypeName(*node_));
  size_t n = node_->size();
  if (n < min_size || n > max_size) {
    if (min_size == max_size) {
      Fail("must have " + std::to_string(min_size) + " elements, got " + std::to_string(n));
    }
    if (n < min_size) Fail("must have at least " + std::to_string(min_size) + " elements, got " + std::to_string(n));
    Fail("must have at most " + std::to_string(max_size) + " elements, got " + std::to_string(n));
  }
  std::vector<Value> out;
  out.reserve(n);
  for (size_t i = 0; i < n; ++i) out.push_back(Child(i));
  return out;
}

std::vector<double> Value::Numbers(size_t size, Range range) const {
  std::vector<double> out;
  for (const Value& v : Array(size, size)) out.push_back(v.Number(range));
  return out;
}

Eigen::Vector3d Value::Vec3(Range range) const {
  auto v = Numbers(3, range);
  return {v[0], v[1], v[2]};
}

std::filesystem::path Value::Path() const {
  std::string s = String();
  if (s.empty()) Fail("must be a non-empty path");
  std::filesystem::path p(s);
  if (p.is_relative()) p = ctx_->base_dir / p;
  return p.lexically_normal();
}

std::filesystem::path Value::ExistingFile(std::string_view what) const {
  const std::filesystem::path p = Path();
  const std::filesystem::path found = FindExportedFile(p);  // Windows separators, letter case
  std::error_code ec;
  if (!std::filesystem::is_regular_file(found, ec)) {
    Fail(std::string(what) + " not found (looked for " + p.string() + ")");
  }
  return found;
}

Object Value::AsObject() const { return Object(*this); }

Value Value::Child(std::string_view key) const {
  if (!node_->is_object()) Fail(std::string("must be an object, got ") + TypeName(*node_));
  auto it = node_->find(std::string(key));
  if (it == node_->end()) Fail("missing required key \"" + std::string(key) + "\"");
  return Value(ctx_, &*it, pointer_ + "/" + EscapePointerToken(key));
}

Value Value::Child(size_t index) const {
  if (!node_->is_array()) Fail(std::string("must be an array, got ") + TypeName(*node_));
  if (index >= node_->size()) Fail("has no element " + std::to_string(index));
  return Value(ctx_, &(*node_)[index], pointer_ + "/" + std::to_string(index));
}

// ---------------------------------------------------------------- Object

Object::Object(const Value& v) : v_(v) {
  if (!v.IsObject()) v.Fail(std::string("must be an object, got ") + TypeName(v.raw()));
}

bool Object::Has(std::string_view key) const {
  known_.emplace(key);
  return v_.raw().contains(std::string(key));
}

Value Object::Get(std::string_view key) const {
  known_.emplace(key);
  if (!v_.raw().contains(std::string(key))) {
    const std::string found = MisspeltKey(v_.raw(), key, known_);
    if (!found.empty()) {
      v_.Fail("missing required key \"" + std::string(key) + "\" (the object has \"" + found +
              "\": misspelt, or in another unit?)");
    }
  }
  return v_.Child(key);
}

std::optional<Value> Object::Find(std::string_view key) const {
  if (!Has(key)) return std::nullopt;
  return v_.Child(key);
}

Object Object::GetObject(std::string_view key) const { return Get(key).AsObject(); }

std::optional<Object> Object::FindObject(std::string_view key) const {
  auto v = Find(key);
  if (!v) return std::nullopt;
  return v->AsObject();
}

double Object::Number(std::string_view key, Range range) const { return Get(key).Number(range); }

double Object::Number(std::string_view key, double fallback, Range range) const {
  auto v = Find(key);
  return v ? v->Number(range) : fallback;
}

int64_t Object::Integer(std::string_view key, Range range) const { return Get(key).Integer(range); }

int64_t Object::Integer(std::string_view key, int64_t fallback, Range range) const {
  auto v = Find(key);
  return v ? v->Integer(range) : fallback;
}

bool Object::Bool(std::string_view key, bool fallback) const {
  auto v = Find(key);
  return v ? v->Bool() : fallback;
}

std::string Object::String(std::string_view key) const { return Get(key).String(); }

std::string Object::String(std::string_view key, const std::string& fallback) const {
  auto v = Find(key);
  return v ? v->String() : fallback;
}

std::string Object::Enum(std::string_view key, std::initializer_list<std::string_view> choices) const {
  return Get(key).Enum(choices);
}

std::string Object::Enum(std::string_view key, std::string_view fallback,
                         std::initializer_list<std::string_view> choices) const {
  auto v = Find(key);
  return v ? v->Enum(choices) : std::string(fallback);
}

Eigen::Vector3d Object::Vec3(std::string_view key, Range range) const { return Get(key).Vec3(range); }

Eigen::Vector3d Object::Vec3(std::string_view key, const Eigen::Vector3d& fallback, Range range) const {
  auto v = Find(key);
  return v ? v->Vec3(range) : fallback;
}

std::filesystem::path Object::Path(std::string_view key) const { return Get(key).Path(); }

void Object::Accept(std::initializer_list<std::string_view> keys) const {
  for (auto k : keys) known_.emplace(k);
}

void Object::Finish() const {
  for (auto it = v_.raw().begin(); it != v_.raw().end(); ++it) {
    if (known_.count(it.key()) == 0) {
      std::string pointer = v_.pointer() + "/" + EscapePointerToken(it.key());
      std::string known_list;
      for (const auto& k : known_) known_list += (known_list.empty() ? "" : ", ") + k;
      throw InputError(v_.file() + ": " + pointer,
                       "unknown key \"" + it.key() + "\"" +
                           (known_list.empty() ? "" : " (known keys: " + known_list + ")"));
    }
  }
}

}  // namespace lt::json

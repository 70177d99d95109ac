#include "core/text_fields.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace lt {

namespace {
bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }
}  // namespace

std::string Lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
  }
  return out;
}

std::optional<double> ParseFiniteNumber(std::string_view text) {
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && (text.front() == '+' || text.front() == '-')) return std::nullopt;
  }
  if (text.empty()) return std::nullopt;
  // from_chars reads "nan" and "inf"; those are not numbers here. Only digits,
  // a point, a sign and an exponent may appear.
  for (char c : text) {
    if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E')) {
      return std::nullopt;
    }
  }
  double v = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string_view TrimBlanks(std::string_view text) {
  while (!text.empty() && IsBlank(text.front())) text.remove_prefix(1);
  while (!text.empty() && IsBlank(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> SplitFields(std::string_view text, char separator) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    size_t pos = text.find(separator, start);
    if (pos == std::string_view::npos) {
      fields.push_back(TrimBlanks(text.substr(start)));
      return fields;
    }
    fields.push_back(TrimBlanks(text.substr(start, pos - start)));
    start = pos + 1;
  }
}

std::string ListFirst(const std::vector<std::string>& items, size_t shown, char quote) {
  const std::string q = quote ? std::string(1, quote) : "";
  std::string list;
  for (size_t i = 0; i < std::min(shown, items.size()); ++i) list += (i ? ", " : "") + q + items[i] + q;
  if (items.size() > shown) list += " and " + std::to_string(items.size() - shown) + " more";
  return list;
}

std::string SizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

double FiniteField(const std::vector<std::string_view>& fields, size_t k, const std::string& where) {
  const std::optional<double> v = ParseFiniteNumber(fields.at(k));
  if (!v) {
    throw InputError(where, "field " + std::to_string(k + 1) + " is not a finite number: '" + std::string(fields[k]) + "'");
  }
  return *v;
}

std::vector<std::string_view> SplitBlanks(std::string_view text) {
  std::vector<std::string_view> fields;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && IsBlank(text[i])) ++i;
    size_t start = i;
    while (i < text.size() && !IsBlank(text[i])) ++i;
    if (i > start) fields.push_back(text.substr(start, i - start));
  }
  return fields;
}

std::string ReadTextFile(const std::filesystem::path& path, const std::string& display_name) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(display_name, "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(display_name, "cannot read file");
  return ss.str();
}

}  // namespace lt

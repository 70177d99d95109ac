#include "pipeline/yaml_scalar.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/error.h"

namespace lt {

bool OpensYamlQuote(const std::string& s, size_t i) {
  if (s[i] != '"' && s[i] != '\'') return false;
  if (i == 0) return true;
  const char p = s[i - 1];
  return p == ' ' || p == '\t' || p == '[' || p == '{' || p == ',' || p == ':' || p == '-';
}

bool FlowBalance::Closed(const std::string& s, char* extra) {
  for (; pos_ < s.size(); ++pos_) {
    const char c = s[pos_];
    if (OpensYamlQuote(s, pos_)) {
      const size_t close = s.find(c, std::max(search_, pos_ + 1));
      if (close == std::string::npos) {
        search_ = s.size();  // the quote is open: the text appended next is searched, not this again
        return false;
      }
      pos_ = close;
    } else if (c == '[' || c == '{') {
      ++depth_;
    } else if ((c == ']' || c == '}') && --depth_ < 0) {
      *extra = c;
      return false;
    }
  }
  return depth_ == 0;
}

std::string StripYamlComment(const std::string& s) {
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
    } else if (OpensYamlQuote(s, i)) {
      quote = c;
    } else if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) {
      return s.substr(0, i);
    }
  }
  return s;
}

bool ReadQuotedScalar(const std::string& s, size_t begin, std::string* value, size_t* end) {
  const char q = s[begin];
  value->clear();
  for (size_t k = begin + 1; k < s.size(); ++k) {
    const char c = s[k];
    if (q == '\'' && c == '\'' && k + 1 < s.size() && s[k + 1] == '\'') {
      *value += '\'';
      ++k;
    } else if (q == '"' && c == '\\' && k + 1 < s.size()) {
      const char n = s[++k];
      *value += n == 'n' ? '\n' : n == 't' ? '\t' : n;
    } else if (c == q) {
      *end = k + 1;
      return true;
    } else {
      *value += c;
    }
  }
  return false;
}

std::string BlockScalarText(const std::vector<std::string>& lines, char style, char chomp) {
  size_t n = lines.size();
  while (n > 0 && lines[n - 1].empty()) --n;
  std::string text;
  for (size_t k = 0; k < n; ++k) {
    if (k > 0) {
      // Folded: a line break between two lines of text at the common indentation
      // is a space; before blank lines it is dropped (each blank line is one).
      size_t next = k;
      while (lines[next].empty()) ++next;  // lines[n - 1] is not empty
      if (style != '>' || lines[k - 1].empty() || lines[k - 1][0] == ' ' || lines[next][0] == ' ') {
        text += '\n';
      } else if (next == k) {
        text += ' ';
      }
    }
    text += lines[k];
  }
  if (n > 0 && chomp != '-') text += '\n';
  if (chomp == '+') text += std::string(lines.size() - n, '\n');
  return text;
}

bool ParseYamlReal(const std::string& s, double* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(*v);
}

namespace {

// ", got 'TEXT'" for a scalar (a collection has no text to show).
std::string Got(const YamlValue& v) { return v.scalar ? ", got '" + *v.scalar + "'" : ""; }

}  // namespace

double YamlNumber(const YamlValue& v) {
  double x = 0;
  if (!v.scalar || v.quoted || !ParseYamlReal(*v.scalar, &x)) {
    throw InputError(v.where, v.name + " must be a finite number" + Got(v));
  }
  return x;
}

long long YamlInteger(const YamlValue& v, long long lo, long long hi) {
  if (v.scalar && !v.quoted && !v.scalar->empty()) {
    char* end = nullptr;
    const long long x = std::strtoll(v.scalar->c_str(), &end, 10);
    if (*end == '\0' && x >= lo && x <= hi) return x;
  }
  throw InputError(v.where, v.name + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" +
                                Got(v));
}

std::string YamlString(const YamlValue& v) {
  if (!v.scalar) throw InputError(v.where, v.name + " must be a string");
  return *v.scalar;
}

}  // namespace lt

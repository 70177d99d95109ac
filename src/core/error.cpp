#include "core/error.h"

#include <cmath>
#include <cstdio>

namespace lt {

std::string FormatNumber(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  // Start with enough digits for the integer part, so 10 prints as "10", not "1e+01".
  int digits = std::abs(v) >= 1 && std::abs(v) < 1e15 ? int(std::floor(std::log10(std::abs(v)))) + 1 : 1;
  for (int precision = digits; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

}  // namespace lt

// Small helpers for checking options structs in src/pipeline: a failed check is
// an lt::InputError naming the option, and numbers in messages are short.
#pragma once

#include <cstdio>
#include <string>

#include "core/error.h"

namespace lt {

// Throws InputError("option NAME", message) unless ok.
inline void Require(bool ok, const char* option, const std::string& message) {
  if (!ok) throw InputError(std::string("option ") + option, message);
}

// A number with `digits` significant digits, for messages.
inline std::string Fmt(double v, int digits = 3) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace lt

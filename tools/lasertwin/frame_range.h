// `--frames A:B` of the run commands (scan, eval): manifest indices [A, B);
// "A:", ":B" and "N" (frame N alone) also work.
#pragma once

#include <string>

#include "core/error.h"

namespace lt::cli {

// Sets *begin and *end (-1: to the end). Throws lt::InputError("--frames", ...).
inline void ParseFrameRange(const std::string& text, int* begin, int* end) {
  auto number = [&](const std::string& s) {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) {
      throw InputError("--frames", "expected whole numbers, got '" + text + "'");
    }
    return std::stoi(s);
  };
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    *begin = number(text);
    *end = *begin + 1;
    return;
  }
  const std::string b = text.substr(0, colon), e = text.substr(colon + 1);
  if (!b.empty()) *begin = number(b);
  if (!e.empty()) *end = number(e);
  if (*end >= 0 && *end <= *begin) throw InputError("--frames", "empty range '" + text + "'");
}

}  // namespace lt::cli

#include "core/frame_range.h"

#include <algorithm>

#include "core/error.h"

namespace lt {

namespace {

int ParseIndex(const std::string& s, const std::string& option, const std::string& text) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 9) {
    throw InputError(option, "expected A:B, A:, :B or N with non-negative integers, got \"" + text + "\"");
  }
  return std::stoi(s);
}

}  // namespace

FrameRange FrameRange::Parse(const std::string& text, const std::string& option) {
  FrameRange r;
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    r.begin = ParseIndex(text, option, text);
    r.end = r.begin + 1;
    return r;
  }
  const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
  if (!a.empty()) r.begin = ParseIndex(a, option, text);
  if (!b.empty()) r.end = ParseIndex(b, option, text);
  if (r.end && *r.end <= r.begin) throw InputError(option, "empty frame range \"" + text + "\"");
  return r;
}

std::pair<int, int> FrameRange::Resolve(int count, const std::string& option) const {
  const int b = begin, e = end ? std::min(*end, count) : count;
  if (b >= e) {
    throw InputError(option, "selects no frame: the scene has " + std::to_string(count) + " frame" +
                                 (count == 1 ? "" : "s") + " (indices 0.." + std::to_string(count - 1) + ")");
  }
  return {b, e};
}

}  // namespace lt

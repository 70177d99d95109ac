// `--frames A:B` of the commands that work on a sequence (render, scan, eval):
// a half-open range of frame indices [begin, end); "A:", ":B", ":" and "N"
// (frame N alone) also work.
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace lt {

struct FrameRange {
  int begin = 0;
  std::optional<int> end;  // nullopt: to the last frame

  // Parses "A:B", "A:", ":B", ":" or "N". Throws InputError naming `option`.
  static FrameRange Parse(const std::string& text, const std::string& option = "--frames");
  // The range within [0, count). Throws InputError naming `option` when it
  // selects no frame.
  std::pair<int, int> Resolve(int count, const std::string& option = "--frames") const;
  // True when the range asks for frames at or past `count` (Resolve drops them).
  bool Exceeds(int count) const { return end ? *end > count : false; }
  // -1 for "to the last frame", as the scan and eval options hold it.
  int EndOrMinusOne() const { return end ? *end : -1; }
};

}  // namespace lt

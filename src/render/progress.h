// Progress of a multi-frame job on stderr: "frame 3/10  1.2 frames/s  ETA 6 s".
// Prints only when stderr is a terminal and not quiet; one line, rewritten.
#pragma once

#include <chrono>
#include <string>

namespace lt {

class Progress {
 public:
  Progress(int total, bool quiet);
  ~Progress();
  void Step(const std::string& what = "frame");  // one unit done
  bool enabled() const { return enabled_; }

 private:
  int total_;
  int done_ = 0;
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace lt

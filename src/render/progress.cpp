#include "render/progress.h"

#include <unistd.h>

#include <cstdio>

namespace lt {

Progress::Progress(int total, bool quiet)
    : total_(total), enabled_(!quiet && ::isatty(STDERR_FILENO)), start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
  if (enabled_ && done_ > 0) std::fputc('\n', stderr);
}

void Progress::Step(const std::string& what) {
  ++done_;
  if (!enabled_) return;
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  double rate = elapsed > 0 ? done_ / elapsed : 0.0;
  double eta = rate > 0 ? (total_ - done_) / rate : 0.0;
  std::fprintf(stderr, "\r%s %d/%d  %.2f/s  ETA %.0f s   ", what.c_str(), done_, total_, rate, eta);
  std::fflush(stderr);
}

}  // namespace lt

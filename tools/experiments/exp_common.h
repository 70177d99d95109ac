// Shared pieces of the experiment programs (tools/experiments/exp_*.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <exception>
#include <iostream>
#include <vector>

namespace lt {

// Nearest-rank quantile (the element at floor(q n) of the sorted values); NaN when empty.
inline double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

// main() of an experiment program: runs `run`, and reports an exception as
// "<name>: error: ..." with exit code 2.
template <typename Run>
int ExperimentMain(const char* name, Run run, int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace lt

#include "pipeline/plane_id_range.h"

#include <algorithm>

namespace lt {

namespace {

// Numberings tried on one line before it counts as undecided (each tried
// numbering costs one check of the whole line).
constexpr int kMostTried = 256;

}  // namespace

int FittingNumberings(const StripeLine& v, long line, int n_planes, const LineFit& fit, std::vector<int>* rank) {
  const size_t k = v.size();
  if (k == 0 || int(k) > n_planes || !fit) return 0;
  std::vector<double> across;
  for (const auto& [x, seg] : v) across.push_back(x);
  // The ranks each stripe alone may take; the numberings are chosen among them.
  std::vector<std::vector<char>> alone(k, std::vector<char>(size_t(n_planes), 0));
  for (size_t j = 0; j < k; ++j) {
    for (int r = int(j); r <= n_planes - int(k - j); ++r) alone[j][size_t(r)] = fit(line, {across[j]}, {r});
  }
  // Every increasing numbering of those ranks, checked as a whole (facing
  // projectors' sheets fit a line only in one order for all its stripes).
  int found = 0, tried = 0;
  std::vector<int> current(k, -1);
  std::function<void(size_t, int)> next = [&](size_t j, int from) {
    if (found > 1 || tried > kMostTried) return;
    if (j == k) {
      ++tried;
      if (fit(line, across, current)) {
        if (++found == 1) *rank = current;
      }
      return;
    }
    for (int r = from; r <= n_planes - int(k - j) && found <= 1; ++r) {
      if (!alone[j][size_t(r)]) continue;
      current[j] = r;
      next(j + 1, r + 1);
    }
  };
  next(0, 0);
  return tried > kMostTried ? 2 : std::min(found, 2);
}

}  // namespace lt

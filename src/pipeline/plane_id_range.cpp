#include "pipeline/plane_id_range.h"

#include <algorithm>
#include <array>

namespace lt {

namespace {

// Readings tried on one line before it counts as undecided (each tried
// reading costs one check of the whole line).
constexpr int kMostTried = 256;

}  // namespace

int FittingNumberings(const StripeLine& v, const std::vector<double>& widths, long line, int n_planes,
                      const LineFit& fit, std::vector<int>* rank) {
  const int k = int(v.size());
  if (k == 0 || k > n_planes || !fit) return 0;
  std::vector<double> across;
  for (const auto& [x, seg] : v) across.push_back(x);
  // The ranks each stripe alone may take, as one sheet (alone[j][r][0]) or
  // as sheets r and r + 1 (alone[j][r][1]); the readings are chosen among them.
  std::vector<std::vector<std::array<char, 2>>> alone(size_t(k), std::vector<std::array<char, 2>>(size_t(n_planes), {0, 0}));
  for (int j = 0; j < k; ++j) {
    const double x = across[size_t(j)], w = widths[size_t(j)];
    for (int r = j; r < n_planes; ++r) {
      alone[size_t(j)][size_t(r)][0] = fit(line, {x}, {w}, {r});
      alone[size_t(j)][size_t(r)][1] = r + 1 < n_planes && fit(line, {x, x}, {w, w}, {r, r + 1});
    }
  }
  // Every reading of the stripes as increasing ranks (a stripe as one sheet,
  // or as two neighbouring ones), checked as a whole: facing projectors'
  // sheets fit a line only in one order for all its stripes.
  int found = 0, tried = 0;
  bool found_double = false;
  std::vector<double> at, width;
  std::vector<int> ranks;
  std::function<void(int, int)> next = [&](int j, int from) {
    if (found > 1 || tried > kMostTried) return;
    if (j == k) {
      ++tried;
      if (fit(line, at, width, ranks) && ++found == 1) {
        found_double = int(ranks.size()) > k;
        *rank = ranks;
      }
      return;
    }
    for (int r = from; r + (k - j) <= n_planes && found <= 1; ++r) {
      for (int sheets = 1; sheets <= 2; ++sheets) {
        if (r + sheets - 1 + (k - j) > n_planes || !alone[size_t(j)][size_t(r)][size_t(sheets - 1)]) continue;
        for (int s = 0; s < sheets; ++s) at.push_back(across[size_t(j)]), width.push_back(widths[size_t(j)]), ranks.push_back(r + s);
        next(j + 1, r + sheets);
        at.resize(at.size() - size_t(sheets)), width.resize(width.size() - size_t(sheets)), ranks.resize(ranks.size() - size_t(sheets));
      }
    }
  };
  next(0, 0);
  if (tried > kMostTried || found > 1 || (found == 1 && found_double)) return 2;
  return found;
}

LinesOfFewer ReadLinesOfFewer(const std::map<long, StripeLine>& lines, int n_planes,
                              const std::map<std::pair<long, int>, double>& width_of, const LineFit& fit,
                              const std::function<bool(long, const StripeLine&)>& skip) {
  LinesOfFewer out;
  for (const auto& [line, v] : lines) {
    if (int(v.size()) >= n_planes || skip(line, v)) continue;
    ++out.lines;
    std::vector<int> rank;
    std::vector<double> widths;
    for (const auto& [x, seg] : v) {
      const auto w = width_of.find({line, seg});
      widths.push_back(w != width_of.end() ? w->second : 0.0);
    }
    const int readings = FittingNumberings(v, widths, line, n_planes, fit, &rank);
    out.several += readings > 1;
    if (readings == 1) out.ranked.push_back({line, std::move(rank)});
  }
  return out;
}

std::string LinesOfFewer::Reason(bool ranged) const {
  if (lines > 0 && !ranged) {
    return " (" + std::to_string(lines) + " show fewer, which could be more than one set of the sheets, e.g. either end's)";
  }
  if (several > 0) {
    return ", and on " + std::to_string(several) + " line(s) of fewer stripes more than one numbering puts them "
           "within the depth range (e.g. both ends' sheets fit it, or a stripe may be two sheets' light)";
  }
  if (lines > 0) {
    return ", and no numbering puts the stripes of the " + std::to_string(lines) + " line(s) of fewer within the depth range";
  }
  return "";
}

}  // namespace lt

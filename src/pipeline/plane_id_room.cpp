#include "pipeline/plane_id_room.h"

#include <algorithm>

namespace lt {

int SheetsOn(const StripeLine& v, size_t from, size_t to, const std::vector<int>& label, int own) {
  std::vector<int> numbers;
  int pieces = 0;
  for (size_t j = from; j < to; ++j) {
    const int other = label[size_t(v[j].second)];
    if (other < 0) ++pieces;
    else if (other != own) numbers.push_back(other);
  }
  std::sort(numbers.begin(), numbers.end());
  return pieces + int(std::unique(numbers.begin(), numbers.end()) - numbers.begin());
}

namespace {

// Whether the numbered stripes of line v stand in increasing order.
bool InOrder(const StripeLine& v, const std::vector<int>& label) {
  int last = -1;
  for (const auto& [x, seg] : v) {
    const int lab = label[size_t(seg)];
    if (lab < 0) continue;
    if (lab < last) return false;
    last = lab;
  }
  return true;
}

}  // namespace

void AddLinesWithoutRoom(const std::map<long, StripeLine>& lines, const std::vector<int>& label, int n_planes,
                         std::vector<std::vector<long>>* lines_of) {
  // The first and last sheet each piece without a number can be, by the
  // stripes beside it on its own lines.
  std::vector<int> lowest(label.size(), 0), highest(label.size(), n_planes - 1);
  for (const auto& [line, v] : lines) {
    if (int(v.size()) > n_planes || !InOrder(v, label)) continue;
    for (size_t k = 0; k < v.size(); ++k) {
      const int seg = v[k].second;
      if (label[size_t(seg)] >= 0) continue;
      lowest[size_t(seg)] = std::max(lowest[size_t(seg)], SheetsOn(v, 0, k, label, -1));
      highest[size_t(seg)] = std::min(highest[size_t(seg)], n_planes - 1 - SheetsOn(v, k + 1, v.size(), label, -1));
    }
  }
  for (const auto& [line, v] : lines) {
    if (int(v.size()) > n_planes || !InOrder(v, label)) continue;
    for (size_t k = 0; k < v.size(); ++k) {
      const int seg = v[k].second, lab = label[size_t(seg)];
      if (lab < 0) continue;
      // Stripe j before it is sheet `first` or later, and the stripes from j
      // on show SheetsOn(j..) sheets; so it is sheet first + that or later.
      int low = 0, high = n_planes - 1;
      for (size_t j = 0; j < k; ++j) {
        const int other = label[size_t(v[j].second)];
        if (other == lab) continue;  // the same sheet's piece across a step
        const int first = other >= 0 ? other : lowest[size_t(v[j].second)];
        low = std::max(low, first + SheetsOn(v, j, k, label, lab));
      }
      for (size_t j = k + 1; j < v.size(); ++j) {
        const int other = label[size_t(v[j].second)];
        if (other == lab) continue;
        const int last = other >= 0 ? other : highest[size_t(v[j].second)];
        high = std::min(high, last - SheetsOn(v, k + 1, j + 1, label, lab));
      }
      if (low > high) continue;  // a blob or a stripe twice: the line does not tell
      if (low > lab || high < lab) (*lines_of)[size_t(seg)].push_back(line);
    }
  }
}

}  // namespace lt

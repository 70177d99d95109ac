// Plane identification by the stripes' order (pipeline/plane_id_order.h),
// internal: the room a search line leaves for each stripe's sheet. On a line,
// stripes of distinct sheets stand in the sheets' order, so a stripe with m
// other sheets' stripes before it is sheet m or later, and with m after it,
// sheet N - 1 - m or earlier. Numbered stripes count by their number (one
// sheet's two pieces at a step count once), each piece without a number as
// one sheet.
#pragma once

#include <cstddef>
#include <map>
#include <utility>
#include <vector>

namespace lt {

// A search line's stripes: (position across, segment), in order across.
using StripeLine = std::vector<std::pair<double, int>>;

// The number of sheets the stripes [from, to) of line v show besides sheet
// `own` (-1: none is left out), by the segments' numbers (`label`, -1: none).
int SheetsOn(const StripeLine& v, size_t from, size_t to, const std::vector<int>& label, int own);

// For each segment numbered in `label`, the lines of at most N stripes (whose
// numbered stripes stand in order) on which the stripes beside it leave it no
// room for its number: those before it are more sheets than its number allows,
// counting, for a piece without a number, the sheets that stand before that
// piece on its own lines (or the other way round after it). Pushed onto
// `lines_of`.
void AddLinesWithoutRoom(const std::map<long, StripeLine>& lines, const std::vector<int>& label, int n_planes,
                         std::vector<std::vector<long>>* lines_of);

}  // namespace lt

// Plane identification by the stripes' order (pipeline/plane_id_order.h),
// internal: a search line of fewer stripes than sheets, read with the
// scanner's working range. Its k stripes may be any k of the N sheets in
// order (N - 1 stripes one spacing apart: either end's sheets); each
// numbering is tried, and the line is numbered when exactly one puts every
// stripe within the range on the sheet it gives (the check: scan's
// SheetsOfRanks::RanksFit, pipeline/plane_id_sheets.h).
#pragma once

#include <functional>
#include <vector>

#include "pipeline/plane_id_room.h"

namespace lt {

// Whether the stripes of search line `line`, at positions `across`, each as
// the sheet of rank `ranks` (0..N-1), lie where the scanner measures.
using LineFit = std::function<bool(long line, const std::vector<double>& across, const std::vector<int>& ranks)>;

// The numberings of line v's stripes (each a rank, increasing across the
// line) that `fit` accepts: 0, 1 (then `rank` holds it) or 2 (two or more,
// or more than can be tried).
int FittingNumberings(const StripeLine& v, long line, int n_planes, const LineFit& fit, std::vector<int>* rank);

}  // namespace lt

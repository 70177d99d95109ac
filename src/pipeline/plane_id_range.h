// Plane identification by the stripes' order (pipeline/plane_id_order.h),
// internal: a search line of fewer stripes than sheets, read with the
// scanner's working range. Its k stripes may be any k of the N sheets in
// order (N - 1 stripes one spacing apart: either end's sheets), and a stripe
// may be two neighbouring sheets' light in one (facing projectors' sheets
// cross). Each such reading is tried, and the line is numbered when exactly
// one puts every stripe within the range on the sheet it gives and it reads
// no stripe as two sheets (the check: scan's SheetsOfRanks::RanksFit,
// pipeline/plane_id_sheets.h).
#pragma once

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/plane_id_room.h"

namespace lt {

// Whether the stripes of search line `line`, at positions `across` with
// widths `widths`, each as the sheet of rank `ranks` (0..N-1, increasing),
// lie where the scanner measures. A stripe read as two sheets' light stands
// twice, at one position, with consecutive ranks.
using LineFit = std::function<bool(long line, const std::vector<double>& across, const std::vector<double>& widths,
                                   const std::vector<int>& ranks)>;

// The readings of line v's stripes (widths by stripe) that `fit` accepts: 0;
// 1, which numbers each stripe as one sheet (then `rank` holds it); or 2 (two
// or more, one reading a stripe as two sheets, or more than can be tried).
int FittingNumberings(const StripeLine& v, const std::vector<double>& widths, long line, int n_planes,
                      const LineFit& fit, std::vector<int>* rank);

// The lines of fewer stripes than sheets, read by FittingNumberings.
struct LinesOfFewer {
  std::vector<std::pair<long, std::vector<int>>> ranked;  // (line, rank of each stripe): one reading fits
  int lines = 0;    // lines of fewer stripes read
  int several = 0;  // of which several readings fit
  // Why they number nothing, for the order's error (" (...)" or ", and ...").
  std::string Reason(bool ranged) const;
};

// Reads the lines of `lines` (widths by (line, segment)) with fewer stripes
// than sheets, but for those `skip` names.
LinesOfFewer ReadLinesOfFewer(const std::map<long, StripeLine>& lines, int n_planes,
                              const std::map<std::pair<long, int>, double>& width_of, const LineFit& fit,
                              const std::function<bool(long, const StripeLine&)>& skip);

}  // namespace lt

#include "pipeline/plane_id_order.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "pipeline/plane_id_room.h"

namespace lt {

namespace {

// Neighbouring stripes on a search line that meets all N are taken for N
// sheets only when they stand within this factor of the frame's median spacing.
constexpr double kSpacingFactor = 3.0;
// Where no line meets all N stripes, a line spans the N sheets when each gap
// between neighbouring stripes is within this many spacings of a whole number.
constexpr double kSpanTolerance = 0.25;
// Fewest lines at a segment's end that give it another rank than its majority
// before the piece there is cut off.
constexpr int kMinCutLines = 2;

using Line = StripeLine;  // (position across, segment), in order across

// A line taken to show all N sheets: its stripes and the sheet of each.
struct RankedLine {
  long line = 0;
  const Line* stripes = nullptr;
  std::vector<int> rank;
};

bool DistinctSegments(const Line& v) {
  std::vector<int> segs;
  for (const auto& [x, seg] : v) segs.push_back(seg);
  std::sort(segs.begin(), segs.end());
  return std::adjacent_find(segs.begin(), segs.end()) == segs.end();
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The number of spacings a gap is (0 when it is no whole number of them).
int Spacings(double gap, double spacing, int n_planes) {
  const double k = gap / spacing;
  const long r = std::lround(k);
  return r >= 1 && r < n_planes && std::abs(k - double(r)) <= kSpanTolerance ? int(r) : 0;
}

// Where no line meets all N stripes: the spacing of neighbouring sheets, the
// largest of the gaps' deciles of which at least 3/4 of all gaps are whole
// multiples (0 when none is): a larger one would leave sheets out, a smaller
// one could count a sheet that is not there.
double SpacingOfMultiples(const std::map<long, Line>& lines, int n_planes) {
  std::vector<double> gaps;
  for (const auto& [line, v] : lines) {
    if (v.size() < 2 || !DistinctSegments(v)) continue;
    for (size_t j = 1; j < v.size(); ++j) gaps.push_back(v[j].first - v[j - 1].first);
  }
  if (gaps.empty()) return 0;
  std::sort(gaps.begin(), gaps.end());
  for (int decile = 10; decile >= 1; --decile) {
    const double candidate = gaps[std::min(gaps.size() - 1, gaps.size() * size_t(decile) / 10)];
    if (!(candidate > 0)) continue;
    size_t fit = 0;
    for (double g : gaps) fit += Spacings(g, candidate, n_planes + 1) > 0;
    if (4 * fit >= 3 * gaps.size()) return candidate;
  }
  return 0;
}

// The lines that meet fewer than N stripes but span the N sheets with the
// missing ones between stripes (gaps of whole spacings adding up to N - 1, one
// of them a single spacing: the spacing seen on the line itself), each stripe
// ranked by the spacings before it.
std::vector<RankedLine> SpanningLines(const std::map<long, Line>& lines, int n_planes, double spacing) {
  std::vector<RankedLine> ranked;
  if (!(spacing > 0)) return ranked;
  for (const auto& [line, v] : lines) {
    if (v.size() < 2 || int(v.size()) >= n_planes || !DistinctSegments(v)) continue;
    std::vector<int> rank(1, 0);
    bool single = false;
    for (size_t j = 1; j < v.size() && rank.size() == j; ++j) {
      const int k = Spacings(v[j].first - v[j - 1].first, spacing, n_planes);
      if (k == 0) break;
      single |= k == 1;
      rank.push_back(rank.back() + k);
    }
    if (rank.size() == v.size() && single && rank.back() == n_planes - 1) ranked.push_back({line, &v, rank});
  }
  return ranked;
}

}  // namespace

StripeOrderPlanes PlanesByStripeOrder(const std::vector<StripeSegment>& segments, const std::vector<int>& candidates,
                                      const std::vector<char>& unnumbered, const std::vector<SegmentEnds>& ends,
                                      const PointAxes& axes, int n_planes, const LineFit& fit) {
  StripeOrderPlanes out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.cut_before.assign(segments.size(), nan);
  out.cut_after.assign(segments.size(), nan);
  // The candidates' points on each search line, in order across.
  std::map<long, Line> lines;
  std::map<std::pair<long, int>, double> width_of;  // a stripe's width by (line, segment)
  for (int s : candidates) {
    for (int i : segments[size_t(s)].points) {
      const long line = std::lround(axes.along[size_t(i)]);
      lines[line].push_back({axes.across[size_t(i)], s});
      if (!axes.width.empty()) width_of[{line, s}] = axes.width[size_t(i)];
    }
  }
  for (auto& [line, v] : lines) std::sort(v.begin(), v.end());

  std::vector<int> label(segments.size(), -1);
  using Votes = std::vector<std::vector<int>>;
  // Labels the undecided segments whose votes agree by at least 3/4; true when any was labelled.
  auto decide = [&](const Votes& votes) {
    bool changed = false;
    for (int s : candidates) {
      if (label[size_t(s)] >= 0 || unnumbered[size_t(s)]) continue;
      const std::vector<int>& v = votes[size_t(s)];
      const int total = std::accumulate(v.begin(), v.end(), 0);
      const int best = int(std::max_element(v.begin(), v.end()) - v.begin());
      if (total > 0 && 4 * v[size_t(best)] >= 3 * total) label[size_t(s)] = best, changed = true;
    }
    return changed;
  };

  // A line on a piece cut off a joined segment (below) neither votes nor
  // numbers by position: whether it shows the sheets of one side of the step or
  // the other, or a spurious stripe where a sheet is missing, is not known.
  auto on_cut_piece = [&](const Line& v) {
    for (const auto& [x, seg] : v) {
      if (unnumbered[size_t(seg)]) return true;
    }
    return false;
  };
  // Lines meeting exactly N distinct segments: each segment's rank is its plane.
  std::vector<RankedLine> ranked;
  for (const auto& [line, v] : lines) {
    if (int(v.size()) != n_planes || !DistinctSegments(v) || on_cut_piece(v)) continue;
    RankedLine r{line, &v, std::vector<int>(size_t(n_planes))};
    std::iota(r.rank.begin(), r.rank.end(), 0);
    ranked.push_back(std::move(r));
  }
  // Neighbouring sheets stand about the same distance apart everywhere in the
  // image (the focal length times the difference of their angles' tangents,
  // whatever the depth, plus a parallax term that only steps change), so a
  // line whose stripes stand far closer or farther apart than the frame's
  // median spacing does not show N sheets: it meets one sheet twice (a depth
  // step) where another is missing. Such lines do not vote, and a piece is not
  // numbered beside a numbered stripe at a distance its rank rules out.
  double spacing = 0;
  const bool full_lines = !ranked.empty();
  if (full_lines) {
    std::vector<double> gaps;
    for (const RankedLine& r : ranked)
      for (size_t j = 1; j < r.stripes->size(); ++j) gaps.push_back((*r.stripes)[j].first - (*r.stripes)[j - 1].first);
    spacing = Median(gaps);
  } else {
    spacing = SpacingOfMultiples(lines, n_planes);
    ranked = SpanningLines(lines, n_planes, spacing);
    ranked.erase(std::remove_if(ranked.begin(), ranked.end(), [&](const RankedLine& r) { return on_cut_piece(*r.stripes); }),
                 ranked.end());
  }
  // Lines of fewer stripes than sheets: numbered where the working range
  // leaves one numbering (their stripes could be several of the sheets).
  std::vector<long> taken;
  for (const RankedLine& r : ranked) taken.push_back(r.line);
  std::sort(taken.begin(), taken.end());
  const LinesOfFewer fewer = ReadLinesOfFewer(lines, n_planes, width_of, fit, [&](long line, const Line& v) {
    return !DistinctSegments(v) || on_cut_piece(v) || std::binary_search(taken.begin(), taken.end(), line);
  });
  for (const auto& [line, rank] : fewer.ranked) ranked.push_back({line, &lines.at(line), rank});
  if (ranked.empty()) {
    out.error = "no search line meets all " + std::to_string(n_planes) + " stripes" + fewer.Reason(bool(fit));
    out.lines_of_fewer = fewer.lines;
    return out;
  }
  // Whether the stripes j0..j1 of line v stand about one spacing apart, each from the next.
  auto spaced = [&](const Line& v, int j0, int j1) {
    if (!(spacing > 0)) return true;
    for (int j = j0 + 1; j <= j1; ++j) {
      const double gap = v[size_t(j)].first - v[size_t(j - 1)].first;
      if (gap < spacing / kSpacingFactor || gap > spacing * kSpacingFactor) return false;
    }
    return true;
  };
  // A line that gives a numbered segment another rank than its other lines'
  // majority shows something that is no sheet (a speckle blob, a reflection)
  // where a sheet is hidden: it does not vote either. The votes are counted
  // again without such lines until none is left.
  std::vector<char> spaced_line(ranked.size());
  for (size_t f = 0; f < ranked.size(); ++f) {
    const RankedLine& r = ranked[f];
    spaced_line[f] = r.rank.back() != int(r.rank.size()) - 1 || spaced(*r.stripes, 0, int(r.stripes->size()) - 1);
  }
  std::vector<char> voting = spaced_line;
  for (bool dropped = true; dropped;) {
    Votes votes(segments.size(), std::vector<int>(size_t(n_planes), 0));
    for (size_t f = 0; f < ranked.size(); ++f) {
      if (!voting[f]) continue;
      for (size_t j = 0; j < ranked[f].rank.size(); ++j) ++votes[size_t((*ranked[f].stripes)[j].second)][size_t(ranked[f].rank[j])];
    }
    std::fill(label.begin(), label.end(), -1);
    decide(votes);
    dropped = false;
    for (size_t f = 0; f < ranked.size(); ++f) {
      for (size_t j = 0; voting[f] && j < ranked[f].rank.size(); ++j) {
        const int lab = label[size_t((*ranked[f].stripes)[j].second)];
        if (lab >= 0 && lab != ranked[f].rank[j]) voting[f] = 0, dropped = true;
      }
    }
  }

  // A segment whose lines give it another rank than their majority only on its
  // first or its last lines (at least kMinCutLines of them, all beyond the
  // lines that agree) is two sheets' pieces joined where a depth step moves
  // the stripes by about one spacing: its piece there is cut off and left
  // without a plane, and the rest is numbered again by its own lines
  // (a blob beside a hidden stripe gives a segment another rank on lines in
  // its middle, and the segment stays whole). Lines whose numbered stripes
  // stand reversed show sheets passing a neighbour at a step (below), not
  // joined pieces, and are not counted.
  // The lines that span the N sheets with some missing show the joins too.
  {
    std::vector<RankedLine> showing;
    for (size_t f = 0; f < ranked.size(); ++f) {
      if (spaced_line[f]) showing.push_back(ranked[f]);
    }
    if (full_lines) {
      std::vector<long> read;  // lines read already (those the working range numbered)
      for (const RankedLine& r : ranked) read.push_back(r.line);
      std::sort(read.begin(), read.end());
      for (RankedLine& r : SpanningLines(lines, n_planes, spacing)) {
        if (!on_cut_piece(*r.stripes) && !std::binary_search(read.begin(), read.end(), r.line)) showing.push_back(std::move(r));
      }
    }
    std::vector<std::vector<std::pair<long, int>>> ranks_of(segments.size());
    for (const RankedLine& r : showing) {
      int last = -1;
      bool reversed = false;
      for (const auto& [x, seg] : *r.stripes) {
        if (label[size_t(seg)] < 0) continue;
        reversed |= label[size_t(seg)] < last;
        last = label[size_t(seg)];
      }
      if (reversed) continue;
      for (size_t j = 0; j < r.rank.size(); ++j) ranks_of[size_t((*r.stripes)[j].second)].push_back({r.line, r.rank[j]});
    }
    // A step that joins one sheet's piece to the next sheet's may leave no line
    // beyond it that meets or spans all N; the pieces beside the joined one
    // there can still leave it no room for its number (plane_id_room.h).
    // Such lines count only beyond the lines that agree: they are read from
    // fewer stripes than a line meeting all N, and one in the middle (a blob
    // beside a piece without a number) does not keep a joined piece whole.
    // Pieces too small to be numbered (noise, or a stripe's few points where
    // extraction lost the rest) count as stripes here: a stripe's few points
    // before the first numbered one are all that may show that a step moved
    // every stripe by a spacing.
    std::map<long, Line> all_lines = lines;
    for (size_t s = 0; s < segments.size(); ++s) {
      if (!segments[s].ignored) continue;
      for (int i : segments[s].points) all_lines[std::lround(axes.along[size_t(i)])].push_back({axes.across[size_t(i)], int(s)});
    }
    for (auto& [line, v] : all_lines) std::sort(v.begin(), v.end());
    std::vector<std::vector<long>> without_room(segments.size());
    AddLinesWithoutRoom(all_lines, label, n_planes, &without_room);
    for (int s : candidates) {
      // A segment without a number (its lines agree by less than 3/4) is
      // taken for the rank most of its lines give it.
      int lab = label[size_t(s)];
      if (lab < 0) {
        std::vector<int> count(size_t(n_planes), 0);
        for (const auto& [line, r] : ranks_of[size_t(s)]) ++count[size_t(r)];
        lab = int(std::max_element(count.begin(), count.end()) - count.begin());
        if (count[size_t(lab)] == 0) continue;
      }
      long agree_lo = std::numeric_limits<long>::max(), agree_hi = std::numeric_limits<long>::min();
      for (const auto& [line, r] : ranks_of[size_t(s)]) {
        if (r == lab) agree_lo = std::min(agree_lo, line), agree_hi = std::max(agree_hi, line);
      }
      int before = 0, after = 0, within = 0;
      for (const auto& [line, r] : ranks_of[size_t(s)]) {
        if (r == lab) continue;
        (line < agree_lo ? before : line > agree_hi ? after : within) += 1;
      }
      if (within > 0) continue;
      if (agree_lo <= agree_hi) {
        for (const long line : without_room[size_t(s)]) before += line < agree_lo, after += line > agree_hi;
      }
      if (before >= kMinCutLines) out.cut_before[size_t(s)] = double(agree_lo);
      if (after >= kMinCutLines) out.cut_after[size_t(s)] = double(agree_hi);
    }
  }

  // Segments never on such a line: the ranks between identified neighbours (or
  // the ends of the line), when exactly the missing ranks lie between them.
  // A segment numbered so that some line's numbered stripes stand out of
  // order is excluded and the positions are read again without it.
  const std::vector<int> by_votes = label;
  std::vector<char> excluded(unnumbered.begin(), unnumbered.end());
  for (bool again = true; again;) {
    label = by_votes;
    for (int pass = 0; pass < n_planes; ++pass) {
      Votes between(segments.size(), std::vector<int>(size_t(n_planes), 0));
      for (const auto& [line, v] : lines) {
        // A line that meets more than N segments, or one numbered sheet twice,
        // shows a piece that is no further sheet: a depth step's second
        // surface (a piece between the other surface's numbered stripes may be
        // any sheet's) or a blob, which may stand in for a hidden sheet in the
        // count between numbered stripes.
        if (int(v.size()) > n_planes || on_cut_piece(v)) continue;
        std::vector<int> numbered;
        for (const auto& [x, seg] : v) {
          if (label[size_t(seg)] >= 0) numbered.push_back(label[size_t(seg)]);
        }
        std::sort(numbered.begin(), numbered.end());
        if (std::adjacent_find(numbered.begin(), numbered.end()) != numbered.end()) continue;
        int prev_label = -1, prev_index = -1;
        for (int k = 0; k <= int(v.size()); ++k) {
          const int lab = k < int(v.size()) ? label[size_t(v[size_t(k)].second)] : n_planes;
          if (lab < 0) continue;
          const int gap = k - prev_index - 1;
          // Neighbours in the run (the numbered stripes at its ends included)
          // must stand about one spacing apart.
          if (gap > 0 && lab - prev_label - 1 == gap &&
              spaced(v, std::max(prev_index, 0), std::min(k, int(v.size()) - 1))) {
            for (int j = 1; j <= gap; ++j) ++between[size_t(v[size_t(prev_index + j)].second)][size_t(prev_label + j)];
          }
          prev_label = lab, prev_index = k;
        }
      }
      for (size_t s = 0; s < segments.size(); ++s) {
        if (excluded[s]) std::fill(between[s].begin(), between[s].end(), 0);
      }
      if (!decide(between)) break;
    }

    // Every line's identified stripes in increasing order. One sheet may meet
    // a line twice where its stripe jumps at a depth step: the piece before the
    // step ends where the piece after it begins, so on the lines they share
    // each of the two runs on past the other's end. A piece whose lines all lie
    // within another's of the same number (a stripe beside a stripe)
    // contradicts. Two pieces numbered by lines that show all N sheets in
    // order may stand reversed on other lines: a thin wall or rib seen by the
    // camera beside sheets that pass it on the surface behind (the order of
    // one projector's sheets holds on a height field, not past thin features).
    auto hand_over = [&](int a, int b) {
      const SegmentEnds &ea = ends[size_t(a)], &eb = ends[size_t(b)];
      return (ea.first_along < eb.first_along && ea.last_along < eb.last_along) ||
             (eb.first_along < ea.first_along && eb.last_along < ea.last_along);
    };
    again = false;
    for (const auto& [line, v] : lines) {
      int last = -1, last_segment = -1;
      for (const auto& [x, seg] : v) {
        const int lab = label[size_t(seg)];
        if (lab < 0) continue;
        const bool twice = lab == last && seg != last_segment && !hand_over(seg, last_segment);
        if (lab < last || twice) {
          const bool voted = by_votes[size_t(seg)] >= 0, last_voted = by_votes[size_t(last_segment)] >= 0;
          if (voted && last_voted && twice) {
            out.error = "the stripes' order contradicts itself on search line " + std::to_string(line);
            return out;
          }
          if (!voted) excluded[size_t(seg)] = 1, again = true;
          if (!last_voted) excluded[size_t(last_segment)] = 1, again = true;
        }
        last = lab, last_segment = seg;
      }
      // A piece numbered by its position leaves room for the stripes beside
      // it: on none of its lines do more other sheets' stripes (the numbered
      // ones by their number, each piece without a number as one) stand
      // before it than its rank, or after it than the sheets after it. A step
      // can join one sheet's piece to the next sheet's beyond it, and the
      // pieces numbered beside that one are then off by one. (Lines meeting
      // more than N segments show two surfaces at a step, or a blob.)
      for (size_t k = 0; int(v.size()) <= n_planes && k < v.size(); ++k) {
        const int seg = v[k].second, lab = label[size_t(seg)];
        if (lab < 0 || by_votes[size_t(seg)] >= 0) continue;
        if (SheetsOn(v, 0, k, label, lab) > lab || SheetsOn(v, k + 1, v.size(), label, lab) > n_planes - 1 - lab) {
          excluded[size_t(seg)] = 1, again = true;
        }
      }
    }
  }
  out.planes = std::move(label);
  return out;
}

}  // namespace lt

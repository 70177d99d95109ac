#include "pipeline/plane_identification.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "core/error.h"

namespace lt {

const char* SegmentTypeName(SegmentType type) {
  switch (type) {
    case SegmentType::kFloating: return "F";
    case SegmentType::kStartEdge: return "LEC";
    case SegmentType::kEndEdge: return "REC";
    case SegmentType::kBothEdges: return "LREC";
  }
  return "?";
}

void PlaneIdOptions::Check() const {
  if (!(std::isfinite(link_distance) && link_distance > 0 && link_distance <= 100)) {
    throw InputError("option link_distance", "must be in (0, 100] pixels, got " + FormatNumber(link_distance));
  }
  if (edge_margin < 0 || edge_margin > 1000) {
    throw InputError("option edge_margin", "must be in [0, 1000] pixels, got " + std::to_string(edge_margin));
  }
  if (min_segment_points < 1) {
    throw InputError("option min_segment_points", "must be >= 1, got " + std::to_string(min_segment_points));
  }
}

namespace {

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Neighbouring stripes on a search line that meets all N are taken for N
// sheets only when they stand within this factor of the frame's median spacing.
constexpr double kSpacingFactor = 3.0;

struct Ends {
  double first_along = 0, first_across = 0;  // mean position on the first search line
  double last_along = 0, last_across = 0;    // and on the last
};

// The plane of each segment (-1: none) by the stripes' order across the image
// (see the header), for the candidate segments (`ends`: each segment's first and
// last search line); empty with *error set when the order cannot decide.
template <typename Along, typename Across>
std::vector<int> PlanesByStripeOrder(const std::vector<StripeSegment>& segments, const std::vector<int>& candidates,
                                     const std::vector<Ends>& ends, int n_planes, Along along, Across across,
                                     std::string* error) {
  // The candidates' points on each search line, in order across.
  std::map<long, std::vector<std::pair<double, int>>> lines;
  for (int s : candidates) {
    for (int i : segments[size_t(s)].points) lines[std::lround(along(i))].push_back({across(i), s});
  }
  for (auto& [line, v] : lines) std::sort(v.begin(), v.end());

  std::vector<int> label(segments.size(), -1);
  using Votes = std::vector<std::vector<int>>;
  // Labels the undecided segments whose votes agree by at least 3/4; true when any was labelled.
  auto decide = [&](const Votes& votes) {
    bool changed = false;
    for (int s : candidates) {
      if (label[size_t(s)] >= 0) continue;
      const std::vector<int>& v = votes[size_t(s)];
      const int total = std::accumulate(v.begin(), v.end(), 0);
      const int best = int(std::max_element(v.begin(), v.end()) - v.begin());
      if (total > 0 && 4 * v[size_t(best)] >= 3 * total) label[size_t(s)] = best, changed = true;
    }
    return changed;
  };

  // Lines meeting exactly N distinct segments: each segment's rank is its plane.
  std::vector<const std::vector<std::pair<double, int>>*> full;
  for (const auto& [line, v] : lines) {
    if (int(v.size()) != n_planes) continue;
    std::vector<int> segs;
    for (const auto& [x, seg] : v) segs.push_back(seg);
    std::sort(segs.begin(), segs.end());
    if (std::adjacent_find(segs.begin(), segs.end()) == segs.end()) full.push_back(&v);
  }
  if (full.empty()) {
    *error = "no search line meets all " + std::to_string(n_planes) + " stripes";
    return {};
  }
  // Neighbouring sheets stand about the same distance apart everywhere in the
  // image (the focal length times the difference of their angles' tangents,
  // whatever the depth, plus a parallax term that only steps change), so a
  // line whose stripes stand far closer or farther apart than the frame's
  // median spacing does not show N sheets: it meets one sheet twice (a depth
  // step) where another is missing. Such lines do not vote, and a piece is not
  // numbered beside a numbered stripe at a distance its rank rules out.
  std::vector<double> gaps;
  for (const auto* v : full)
    for (size_t r = 1; r < v->size(); ++r) gaps.push_back((*v)[r].first - (*v)[r - 1].first);
  double spacing = 0;
  if (!gaps.empty()) {
    std::nth_element(gaps.begin(), gaps.begin() + long(gaps.size() / 2), gaps.end());
    spacing = gaps[gaps.size() / 2];
  }
  // Whether the stripes j0..j1 of line v stand about one spacing apart, each from the next.
  auto spaced = [&](const std::vector<std::pair<double, int>>& v, int j0, int j1) {
    if (!(spacing > 0)) return true;
    for (int j = j0 + 1; j <= j1; ++j) {
      const double gap = v[size_t(j)].first - v[size_t(j - 1)].first;
      if (gap < spacing / kSpacingFactor || gap > spacing * kSpacingFactor) return false;
    }
    return true;
  };
  // A line that meets N segments but gives one of them another rank than its
  // other lines' majority shows something that is no sheet (a speckle blob, a
  // reflection) where a sheet is hidden: it does not vote either. The votes are
  // counted again without such lines until none is left.
  std::vector<char> voting(full.size());
  for (size_t f = 0; f < full.size(); ++f) voting[f] = spaced(*full[f], 0, n_planes - 1);
  for (bool dropped = true; dropped;) {
    Votes votes(segments.size(), std::vector<int>(size_t(n_planes), 0));
    for (size_t f = 0; f < full.size(); ++f) {
      if (!voting[f]) continue;
      for (int r = 0; r < n_planes; ++r) ++votes[size_t((*full[f])[size_t(r)].second)][size_t(r)];
    }
    std::fill(label.begin(), label.end(), -1);
    decide(votes);
    dropped = false;
    for (size_t f = 0; f < full.size(); ++f) {
      for (int r = 0; voting[f] && r < n_planes; ++r) {
        const int lab = label[size_t((*full[f])[size_t(r)].second)];
        if (lab >= 0 && lab != r) voting[f] = 0, dropped = true;
      }
    }
  }

  // Segments never on such a line: the ranks between identified neighbours (or
  // the ends of the line), when exactly the missing ranks lie between them.
  // A segment numbered so that some line's numbered stripes stand out of
  // order is excluded and the positions are read again without it.
  const std::vector<int> by_votes = label;
  std::vector<char> excluded(segments.size(), 0);
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
        if (int(v.size()) > n_planes) continue;
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
      const Ends &ea = ends[size_t(a)], &eb = ends[size_t(b)];
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
            *error = "the stripes' order contradicts itself on search line " + std::to_string(line);
            return {};
          }
          if (!voted) excluded[size_t(seg)] = 1, again = true;
          if (!last_voted) excluded[size_t(last_segment)] = 1, again = true;
        }
        last = lab, last_segment = seg;
      }
    }
  }
  return label;
}

}  // namespace

PlaneIdentification IdentifyPlanes(const std::vector<StripePoint>& points, const PixelRect& region, int n_planes,
                                   const PlaneIdOptions& options) {
  options.Check();
  if (n_planes < 1) throw InputError("option planes", "must be >= 1, got " + std::to_string(n_planes));
  PlaneIdentification result;
  result.points = points;
  for (auto& p : result.points) p.plane = -1;
  const bool rows = options.axis == SearchAxis::kRows;
  const int n = int(points.size());
  auto along = [&](int i) { return rows ? points[i].v : points[i].u; };
  auto across = [&](int i) { return rows ? points[i].u : points[i].v; };

  // 1. Connected components over adjacent search lines.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    double la = std::round(along(a)), lb = std::round(along(b));
    return la != lb ? la < lb : across(a) < across(b);
  });
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const double link = options.link_distance;
  int prev_begin = 0, prev_end = 0;
  for (int i = 0; i < n;) {
    const double line = std::round(along(order[i]));
    int e = i;
    while (e < n && std::round(along(order[e])) == line) ++e;
    const bool prev_adjacent = prev_end > prev_begin && std::round(along(order[prev_begin])) == line - 1;
    int p = prev_begin;
    for (int k = i; k < e; ++k) {
      const double x = across(order[k]);
      if (k > i && x - across(order[k - 1]) <= link) parent[Find(parent, order[k])] = Find(parent, order[k - 1]);
      if (!prev_adjacent) continue;
      while (p < prev_end && across(order[p]) < x - link) ++p;
      for (int q = p; q < prev_end && across(order[q]) <= x + link; ++q) {
        int ra = Find(parent, order[k]), rb = Find(parent, order[q]);
        if (ra != rb) parent[ra] = rb;
      }
    }
    prev_begin = i;
    prev_end = e;
    i = e;
  }
  std::vector<int> segment_of(n, -1);
  for (int k = 0; k < n; ++k) {  // segments numbered in order of their first point
    const int i = order[k], r = Find(parent, i);
    if (segment_of[r] < 0) {
      segment_of[r] = int(result.segments.size());
      result.segments.emplace_back();
    }
    result.segments[segment_of[r]].points.push_back(i);
  }

  // 2. Classification (thesis Algorithm 1) and segment ends.
  const double start = rows ? region.y : region.x;
  const double end = start + (rows ? region.height : region.width) - 1;
  std::vector<Ends> ends(result.segments.size());
  std::vector<int> candidates;  // segment indices taking part in grouping
  for (size_t s = 0; s < result.segments.size(); ++s) {
    StripeSegment& seg = result.segments[s];
    bool at_start = false, at_end = false;
    for (int i : seg.points) {
      at_start |= along(i) <= start + options.edge_margin;
      at_end |= along(i) >= end - options.edge_margin;
    }
    seg.type = at_start && at_end ? SegmentType::kBothEdges
               : at_start         ? SegmentType::kStartEdge
               : at_end           ? SegmentType::kEndEdge
                                  : SegmentType::kFloating;
    seg.ignored = int(seg.points.size()) < options.min_segment_points;
    Ends& e = ends[s];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i : seg.points) lo = std::min(lo, std::round(along(i))), hi = std::max(hi, std::round(along(i)));
    int nlo = 0, nhi = 0;
    for (int i : seg.points) {
      if (std::round(along(i)) == lo) e.first_across += across(i), ++nlo;
      if (std::round(along(i)) == hi) e.last_across += across(i), ++nhi;
    }
    e.first_along = lo, e.last_along = hi;
    e.first_across /= nlo, e.last_across /= nhi;
    if (!seg.ignored) candidates.push_back(int(s));
  }

  // 3. Grouping: a chain starts at each start-edge segment and grows by the
  // shortest connection vector from a chain's end to the start of a free
  // segment further along, shortest first over all chains, until it reaches
  // an end-edge segment.
  struct Chain {
    std::vector<int> segments;
    bool closed = false;
  };
  std::vector<Chain> chains;
  std::vector<char> used(result.segments.size(), 0);
  for (int s : candidates) {
    const SegmentType t = result.segments[s].type;
    if (t == SegmentType::kStartEdge || t == SegmentType::kBothEdges) {
      chains.push_back({{s}, t == SegmentType::kBothEdges});
      used[s] = 1;
    }
  }
  for (;;) {
    double best = std::numeric_limits<double>::infinity();
    int best_chain = -1, best_seg = -1;
    for (size_t c = 0; c < chains.size(); ++c) {
      if (chains[c].closed) continue;
      const Ends& tail = ends[chains[c].segments.back()];
      for (int s : candidates) {
        if (used[s]) continue;
        const SegmentType t = result.segments[s].type;
        if (t != SegmentType::kFloating && t != SegmentType::kEndEdge) continue;
        if (ends[s].first_along <= tail.last_along) continue;  // must continue further along
        const double d = std::hypot(ends[s].first_along - tail.last_along, ends[s].first_across - tail.last_across);
        if (d < best) best = d, best_chain = int(c), best_seg = s;
      }
    }
    if (best_chain < 0) break;
    chains[best_chain].segments.push_back(best_seg);
    used[best_seg] = 1;
    if (result.segments[best_seg].type == SegmentType::kEndEdge) chains[best_chain].closed = true;
  }

  result.groups_found = int(chains.size());
  int unjoined = 0;
  for (int s : candidates) unjoined += !used[s];
  std::string chains_error;
  std::vector<int> by_chains;
  if (int(chains.size()) != n_planes || unjoined > 0) {
    chains_error = "found " + std::to_string(chains.size()) + " stripe group(s) starting at the " +
                   (rows ? "top" : "left") + " edge, expected " + std::to_string(n_planes);
    if (unjoined > 0) chains_error += "; " + std::to_string(unjoined) + " segment(s) could not be joined to a group";
  } else {
    // 4. Plane numbers across the image, by position at the start edge.
    std::vector<int> chain_order(chains.size());
    std::iota(chain_order.begin(), chain_order.end(), 0);
    std::sort(chain_order.begin(), chain_order.end(), [&](int a, int b) {
      return ends[chains[a].segments.front()].first_across < ends[chains[b].segments.front()].first_across;
    });
    by_chains.assign(result.segments.size(), -1);
    for (int id = 0; id < int(chain_order.size()); ++id) {
      for (int s : chains[chain_order[id]].segments) by_chains[size_t(s)] = id;
    }
  }

  // The stripes' order decides; the chains when it cannot.
  std::string order_error;
  std::vector<int> planes = PlanesByStripeOrder(result.segments, candidates, ends, n_planes, along, across, &order_error);
  result.method = PlaneIdMethod::kStripeOrder;
  if (planes.empty()) {
    if (by_chains.empty()) {
      result.error = "the stripes' order cannot number them (" + order_error + ") and the edge chains cannot (" +
                     chains_error + ")";
      return result;
    }
    planes = std::move(by_chains);
    result.method = PlaneIdMethod::kEdgeChains;
    result.order_error = order_error;
  }
  for (int s : candidates) {
    const int plane = planes[size_t(s)];
    if (plane < 0) {
      ++result.unidentified_segments;
      continue;
    }
    result.segments[size_t(s)].plane = plane;
    for (int i : result.segments[size_t(s)].points) result.points[size_t(i)].plane = plane;
  }
  result.ok = true;
  return result;
}

}  // namespace lt

#include "pipeline/plane_identification.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.h"
#include "pipeline/plane_id_order.h"

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

}  // namespace

PlaneIdentification IdentifyPlanes(const std::vector<StripePoint>& points, const PixelRect& region, int n_planes,
                                   const PlaneIdOptions& options, const RankFit& range_fit) {
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
  std::vector<SegmentEnds> ends(result.segments.size());
  auto classify = [&](size_t s) {
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
    SegmentEnds& e = ends[s];
    e = SegmentEnds{};
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i : seg.points) lo = std::min(lo, std::round(along(i))), hi = std::max(hi, std::round(along(i)));
    int nlo = 0, nhi = 0;
    for (int i : seg.points) {
      if (std::round(along(i)) == lo) e.first_across += across(i), ++nlo;
      if (std::round(along(i)) == hi) e.last_across += across(i), ++nhi;
    }
    e.first_along = lo, e.last_along = hi;
    e.first_across /= nlo, e.last_across /= nhi;
  };
  std::vector<int> candidates;  // segment indices taking part in grouping
  for (size_t s = 0; s < result.segments.size(); ++s) {
    classify(s);
    result.segments[s].ignored = int(result.segments[s].points.size()) < options.min_segment_points;
    if (!result.segments[s].ignored) candidates.push_back(int(s));
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
      const SegmentEnds& tail = ends[chains[c].segments.back()];
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

  // The stripes' order decides; the chains when it cannot. A segment the order
  // finds joined of two sheets' pieces is cut, the piece beyond the cut kept
  // without a plane, and the order read again.
  PointAxes axes;
  axes.along.resize(size_t(n)), axes.across.resize(size_t(n)), axes.width.resize(size_t(n));
  for (int i = 0; i < n; ++i) {
    axes.along[size_t(i)] = along(i), axes.across[size_t(i)] = across(i), axes.width[size_t(i)] = points[size_t(i)].width;
  }
  std::vector<char> cut_off(result.segments.size(), 0);
  LineFit line_fit;
  if (range_fit) {
    line_fit = [&](long line, const std::vector<double>& across_at, const std::vector<double>& widths,
                   const std::vector<int>& ranks) {
      std::vector<StripePoint> line_points(across_at.size());
      for (size_t j = 0; j < across_at.size(); ++j) {
        StripePoint& p = line_points[j];
        (rows ? p.u : p.v) = across_at[j];
        (rows ? p.v : p.u) = double(line);
        p.width = widths[j];
        p.plane = ranks[j];
      }
      return range_fit(line_points);
    };
  }
  StripeOrderPlanes by_order;
  for (bool cut = true; cut;) {
    by_order = PlanesByStripeOrder(result.segments, candidates, cut_off, ends, axes, n_planes, line_fit);
    cut = false;
    for (size_t s = 0, count = result.segments.size(); s < count; ++s) {
      const double before = by_order.cut_before[s], after = by_order.cut_after[s];
      if (std::isnan(before) && std::isnan(after)) continue;
      std::vector<int> kept, lower, upper;
      for (int i : result.segments[s].points) {
        const double line = std::round(along(i));
        (line < before ? lower : line > after ? upper : kept).push_back(i);
      }
      result.segments[s].points = std::move(kept);
      classify(s);
      for (std::vector<int>* piece : {&lower, &upper}) {
        if (piece->empty()) continue;
        StripeSegment cut_piece;
        cut_piece.points = std::move(*piece);
        result.segments.push_back(std::move(cut_piece));
        ends.emplace_back();
        classify(result.segments.size() - 1);
        cut_off.push_back(1);
        candidates.push_back(int(result.segments.size()) - 1);
      }
      cut = true;
    }
  }
  std::vector<int> planes = std::move(by_order.planes);
  const std::string order_error = by_order.error;
  result.method = PlaneIdMethod::kStripeOrder;
  if (planes.empty()) {
    if (by_chains.empty()) {
      result.lines_of_fewer_stripes = by_order.lines_of_fewer;
      result.error = "the stripes' order cannot number them (" + order_error + ") and the edge chains cannot (" +
                     chains_error + ")";
      return result;
    }
    planes = std::move(by_chains);
    planes.resize(result.segments.size(), -1);
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

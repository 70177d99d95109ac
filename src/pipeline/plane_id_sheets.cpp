#include "pipeline/plane_id_sheets.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>

#include "core/error.h"
#include "core/text_fields.h"

namespace lt {

namespace {

// The depths (metres) over which the sheets' order is read.
constexpr double kNearest = 1e-3, kFarthest = 1e3;
// Two sheets closer than this (pixels) across the image make one stripe, or
// two whose order a fraction of a pixel's error in their positions may swap.
constexpr double kMergedPx = 3.0;
// How far (pixels) a stripe's measured position may stand from its sheet's:
// an order fits a point that far beyond the depths where it holds.
constexpr double kToleratedPx = 0.5;

// Where a plane stands across the search line through the normalised image
// point (x, y) (x / z searching rows, along the line y = const; y / z searching
// columns) is alpha + beta w at inverse depth w = 1 / z: a straight line in w,
// so two sheets cross at most once on a search line.
struct Across {
  double alpha = 0, beta = 0;
  double at_infinity = 0;  // +-inf for a plane parallel to the search direction's normal, else 0

  Across(const Plane& p, bool rows, double x, double y) {
    const double a = rows ? p.n.x() : p.n.y();
    const double c = (rows ? p.n.y() * y : p.n.x() * x) + p.n.z();
    if (std::abs(a) < 1e-12) {
      at_infinity = std::copysign(std::numeric_limits<double>::infinity(), -c);
    } else {
      alpha = -c / a, beta = -p.d / a;
    }
  }
  double At(double w) const { return at_infinity != 0 ? at_infinity : alpha + beta * w; }
};

std::vector<Across> AcrossLine(const std::vector<Plane>& planes, bool rows, double x, double y) {
  std::vector<Across> out;
  for (const Plane& p : planes) out.emplace_back(p, rows, x, y);
  return out;
}

// The orders the sheets take across a search line at inverse depths from
// w_min to w_max, each over the inverse depths [w_lo, w_hi) where it holds.
struct OrderRun {
  std::vector<int> order;
  double w_lo, w_hi;
};
std::vector<OrderRun> OrdersOverDepth(const std::vector<Across>& line, double w_min = 1 / kFarthest,
                                      double w_max = 1 / kNearest) {
  std::vector<double> ws = {w_min, w_max};
  for (size_t p = 0; p < line.size(); ++p) {
    for (size_t q = p + 1; q < line.size(); ++q) {
      if (line[p].at_infinity != 0 || line[q].at_infinity != 0 || line[p].beta == line[q].beta) continue;
      const double w = (line[q].alpha - line[p].alpha) / (line[p].beta - line[q].beta);
      if (w > w_min && w < w_max) ws.push_back(w);
    }
  }
  std::sort(ws.begin(), ws.end());
  std::vector<OrderRun> runs;
  for (size_t i = 0; i + 1 < ws.size(); ++i) {
    if (!(ws[i + 1] > ws[i])) continue;
    const double mid = 0.5 * (ws[i] + ws[i + 1]);
    std::vector<int> order(line.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return line[size_t(a)].At(mid) < line[size_t(b)].At(mid); });
    if (!runs.empty() && runs.back().order == order) {
      runs.back().w_hi = ws[i + 1];
    } else {
      runs.push_back({std::move(order), ws[i], ws[i + 1]});
    }
  }
  return runs;
}

// The inverse depth at which `ray` (camera frame) meets `plane` (negative or
// not finite behind the camera or parallel to it).
double InverseDepth(const Plane& plane, const Eigen::Vector3d& ray) {
  return 1 / (-plane.d / plane.n.dot(ray) * ray.z());
}

// The inverse depth that moves sheet `here`'s stripe by kToleratedPx.
double ToleratedInverseDepth(const Across& here, double focal) { return kToleratedPx / (focal * std::abs(here.beta)); }

}  // namespace

void DepthRange::Check(const std::string& where) const {
  if (!(std::isfinite(near_m) && std::isfinite(far_m) && near_m > 0 && far_m > near_m)) {
    std::ostringstream s;
    s << "the depth range must be 0 < MIN < MAX (finite), got " << near_m * 1e3 << ":" << far_m * 1e3 << " mm";
    throw InputError(where, s.str());
  }
}

DepthRange ParseDepthRange(const std::string& text, const std::string& where) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos) throw InputError(where, "expected MIN_MM:MAX_MM (camera z), got '" + text + "'");
  const std::optional<double> near_mm = ParseFiniteNumber(text.substr(0, colon));
  const std::optional<double> far_mm = ParseFiniteNumber(text.substr(colon + 1));
  if (!near_mm || !far_mm) throw InputError(where, "expected MIN_MM:MAX_MM (two numbers), got '" + text + "'");
  const DepthRange range{*near_mm / 1e3, *far_mm / 1e3};
  range.Check(where);
  return range;
}

SheetsOfRanks::SheetsOfRanks(const Triangulator& triangulator, SearchAxis axis, std::optional<DepthRange> range)
    : triangulator_(triangulator),
      axis_(axis),
      ranged_(range.has_value()),
      w_min_(range ? 1 / range->far_m : 1 / kFarthest),
      w_max_(range ? 1 / range->near_m : 1 / kNearest),
      order_(PlanesInImageOrder(triangulator.planes(), axis)) {
  if (range) range->Check("depth range");
  // Whether the order changes in front of the camera (1 mm to 1 km), read on
  // the central search line and lines half way to the image's edges
  // (normalised coordinate +-0.5).
  const bool rows = axis == SearchAxis::kRows;
  for (double line : {-0.5, 0.0, 0.5}) {
    depth_dependent_ |= OrdersOverDepth(AcrossLine(triangulator.planes(), rows, rows ? 0 : line, rows ? line : 0)).size() > 1;
  }
}

int SheetsOfRanks::Apply(std::vector<StripePoint>* points) const {
  const std::vector<Plane>& planes = triangulator_.planes();
  const bool rows = axis_ == SearchAxis::kRows;
  const double focal = rows ? triangulator_.camera().fx() : triangulator_.camera().fy();
  // Whether a point on plane k lies outside the depth range.
  auto outside = [&](const Eigen::Vector3d& ray, int k) {
    const double w = InverseDepth(planes[size_t(k)], ray);
    return ranged_ && !(w >= w_min_ && w <= w_max_);
  };
  if (!depth_dependent_) {
    int dropped = 0;
    for (StripePoint& p : *points) {
      if (p.plane < 0) continue;
      p.plane = p.plane < int(order_.size()) ? order_[size_t(p.plane)] : -1;
      if (p.plane >= 0 && ranged_) {
        const std::optional<Eigen::Vector3d> ray = triangulator_.camera().Unproject({p.u, p.v});
        if (!ray || outside(*ray, p.plane)) p.plane = -1;
      }
      dropped += p.plane < 0;
    }
    return dropped;
  }
  // The ranked points of each search line, with their rays.
  struct Ranked {
    size_t index;
    int rank;
    Eigen::Vector3d ray;  // unit, camera frame
  };
  std::map<long, std::vector<Ranked>> lines;
  int dropped = 0;
  for (size_t i = 0; i < points->size(); ++i) {
    StripePoint& p = (*points)[i];
    if (p.plane < 0) continue;
    const int rank = p.plane;
    p.plane = -1;
    const std::optional<Eigen::Vector3d> ray = triangulator_.camera().Unproject({p.u, p.v});
    if (!ray || !(ray->z() > 0) || rank >= int(planes.size())) {
      ++dropped;
      continue;
    }
    lines[std::lround(rows ? p.v : p.u)].push_back({i, rank, *ray});
  }
  for (const auto& [line, ranked] : lines) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Ranked& r : ranked) mean += r.ray / r.ray.z();
    mean /= double(ranked.size());
    const std::vector<OrderRun> runs = OrdersOverDepth(AcrossLine(planes, rows, mean.x(), mean.y()), w_min_, w_max_);
    // Stripes measured within kMergedPx of another on the line: their order,
    // and so their ranks, are not certain.
    std::vector<char> uncertain(ranked.size(), 0);
    for (size_t j = 0; j < ranked.size(); ++j) {
      const StripePoint& pj = (*points)[ranked[j].index];
      for (size_t i = 0; i < ranked.size(); ++i) {
        const StripePoint& pi = (*points)[ranked[i].index];
        uncertain[j] |= i != j && std::abs(rows ? pi.u - pj.u : pi.v - pj.v) < kMergedPx;
      }
    }
    // An order fits the line when each of its points, on the plane the order
    // gives its rank, lies in front of the camera at a depth where the order
    // holds, give or take kToleratedPx of its position (the surface across
    // the line at about one depth, as the order across the image assumes),
    // and when no point of the line, measured apart from the others, would
    // be two sheets' light in one stripe (another sheet within half kMergedPx
    // of it). A point's plane is the one every fitting order gives its rank;
    // none when no order fits, or when in a fitting order another sheet stands
    // within kMergedPx of it.
    std::vector<int> plane(ranked.size(), -2);  // -2: no fitting order yet
    for (const OrderRun& run : runs) {
      bool fits = true;
      std::vector<char> close(ranked.size(), 0);
      for (size_t j = 0; j < ranked.size() && fits; ++j) {
        const Ranked& r = ranked[j];
        const int k = run.order[size_t(r.rank)];
        const Plane& sheet = planes[size_t(k)];
        const double w = InverseDepth(sheet, r.ray);
        const std::vector<Across> here = AcrossLine(planes, rows, r.ray.x() / r.ray.z(), r.ray.y() / r.ray.z());
        const double dw = ToleratedInverseDepth(here[size_t(k)], focal);
        fits = std::isfinite(w) && w > 0 && w >= run.w_lo - dw && w < run.w_hi + dw;
        double nearest = std::numeric_limits<double>::infinity();
        for (size_t q = 0; q < planes.size(); ++q) {
          if (int(q) != k) nearest = std::min(nearest, std::abs(here[q].At(w) - here[size_t(k)].At(w)) * focal);
        }
        fits = fits && (nearest >= 0.5 * kMergedPx || uncertain[j]);
        close[j] = nearest < kMergedPx;
      }
      if (!fits) continue;
      for (size_t j = 0; j < ranked.size(); ++j) {
        const int k = run.order[size_t(ranked[j].rank)];
        plane[j] = plane[j] == -2 || plane[j] == k ? k : -1;
        uncertain[j] |= close[j];
      }
    }
    for (size_t j = 0; j < ranked.size(); ++j) {
      if (uncertain[j] || (plane[j] >= 0 && outside(ranked[j].ray, plane[j]))) plane[j] = -1;
    }
    for (size_t j = 0; j < ranked.size(); ++j) {
      if (plane[j] >= 0) {
        (*points)[ranked[j].index].plane = plane[j];
      } else {
        ++dropped;
      }
    }
  }
  return dropped;
}

bool SheetsOfRanks::RanksFit(const std::vector<StripePoint>& points) const {
  const std::vector<Plane>& planes = triangulator_.planes();
  const bool rows = axis_ == SearchAxis::kRows;
  const double focal = rows ? triangulator_.camera().fx() : triangulator_.camera().fy();
  std::vector<Eigen::Vector3d> rays;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const StripePoint& p : points) {
    const std::optional<Eigen::Vector3d> ray = triangulator_.camera().Unproject({p.u, p.v});
    if (p.plane < 0 || p.plane >= int(planes.size()) || !ray || !(ray->z() > 0)) return false;
    rays.push_back(*ray);
    mean += *ray / ray->z();
  }
  if (rays.empty()) return false;
  mean /= double(rays.size());
  // One projector: one order at every depth (Apply's). Facing projectors:
  // the orders the sheets take on this line at depths within the range.
  const std::vector<OrderRun> runs = depth_dependent_
                                         ? OrdersOverDepth(AcrossLine(planes, rows, mean.x(), mean.y()), w_min_, w_max_)
                                         : std::vector<OrderRun>{{order_, w_min_, w_max_}};
  for (const OrderRun& run : runs) {
    bool fits = true;
    for (size_t j = 0; j < points.size() && fits; ++j) {
      const Eigen::Vector3d& ray = rays[j];
      const std::vector<Across> here = AcrossLine(planes, rows, ray.x() / ray.z(), ray.y() / ray.z());
      // The inverse depths where the point's sheet(s) stand within `px` of it.
      double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
      bool in_front = true;
      auto within = [&](int k, double px) {
        const double w = InverseDepth(planes[size_t(k)], ray);
        const double dw = px / kToleratedPx * ToleratedInverseDepth(here[size_t(k)], focal);
        in_front &= std::isfinite(w) && w > 0;
        lo = std::max(lo, w - dw), hi = std::min(hi, w + dw);
      };
      // A stripe read as two sheets' light stands twice at one position: its
      // centre lies between theirs, both within half its width (at least
      // kMergedPx) of it at one depth.
      if (j + 1 < points.size() && points[j + 1].u == points[j].u && points[j + 1].v == points[j].v) {
        const double half = 0.5 * std::max(kMergedPx, points[j].width);
        within(run.order[size_t(points[j].plane)], half);
        within(run.order[size_t(points[j + 1].plane)], half);
        ++j;
      } else {
        within(run.order[size_t(points[j].plane)], kToleratedPx);
      }
      fits = in_front && lo <= hi && lo <= run.w_hi && hi >= run.w_lo;
    }
    if (fits) return true;
  }
  return false;
}

}  // namespace lt

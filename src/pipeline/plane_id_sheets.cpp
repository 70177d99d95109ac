#include "pipeline/plane_id_sheets.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace lt {

namespace {

// Where plane p stands across the search line through the normalised image
// point (x, y) at depth z: x / z searching rows (the line y = const), y / z
// searching columns.
double PositionAcross(const Plane& p, bool rows, double x, double y, double z) {
  const double a = rows ? p.n.x() : p.n.y();
  const double rest = (rows ? p.n.y() * y : p.n.x() * x) * z + p.n.z() * z + p.d;
  if (std::abs(a) < 1e-12) return std::copysign(std::numeric_limits<double>::infinity(), -rest);
  return -rest / (a * z);
}

// The planes in order across the search line through (x, y) at depth z.
std::vector<int> OrderAt(const std::vector<Plane>& planes, bool rows, double x, double y, double z) {
  std::vector<int> order(planes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return PositionAcross(planes[size_t(a)], rows, x, y, z) < PositionAcross(planes[size_t(b)], rows, x, y, z);
  });
  return order;
}

// The depths (metres) over which the sheets' order is read.
constexpr double kNearest = 1e-3, kFarthest = 1e3, kDepthStep = 1.02;
// Two sheets closer than this (pixels) across the image make one stripe.
constexpr double kMergedPx = 2.0;

}  // namespace

SheetsOfRanks::SheetsOfRanks(const Triangulator& triangulator, SearchAxis axis)
    : triangulator_(triangulator), axis_(axis), order_(PlanesInImageOrder(triangulator.planes(), axis)) {
  // The order on the central search line and on lines half way to the image's
  // edges (normalised coordinate +-0.5), at depths from 1 mm to 1 km.
  const bool rows = axis == SearchAxis::kRows;
  const std::vector<Plane>& planes = triangulator.planes();
  for (double line : {-0.5, 0.0, 0.5}) {
    std::vector<int> first;
    for (double z = kNearest; z <= kFarthest && !depth_dependent_; z *= kDepthStep) {
      const std::vector<int> order = OrderAt(planes, rows, rows ? 0 : line, rows ? line : 0, z);
      if (first.empty()) first = order;
      depth_dependent_ = order != first;
    }
  }
}

int SheetsOfRanks::Apply(std::vector<StripePoint>* points) const {
  const std::vector<Plane>& planes = triangulator_.planes();
  const bool rows = axis_ == SearchAxis::kRows;
  const double focal = rows ? triangulator_.camera().fx() : triangulator_.camera().fy();
  if (!depth_dependent_) {
    for (StripePoint& p : *points) {
      if (p.plane >= 0) p.plane = p.plane < int(order_.size()) ? order_[size_t(p.plane)] : -1;
    }
    return 0;
  }
  // The ranked points of each search line, with their normalised image position.
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
    // The orders the sheets take on this line at depths from 1 mm to 1 km,
    // each over the depths where it holds (its ends found by bisection).
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Ranked& r : ranked) mean += r.ray / r.ray.z();
    mean /= double(ranked.size());
    auto order_at = [&](double z) { return OrderAt(planes, rows, mean.x(), mean.y(), z); };
    struct Run {
      std::vector<int> order;
      double z_lo, z_hi;
    };
    std::vector<Run> runs{{order_at(kNearest), 0, std::numeric_limits<double>::infinity()}};
    for (double z = kNearest, next = z * kDepthStep; next <= kFarthest; z = next, next *= kDepthStep) {
      std::vector<int> order = order_at(next);
      if (order == runs.back().order) continue;
      double lo = z, hi = next;
      for (int i = 0; i < 40; ++i) {
        const double mid = 0.5 * (lo + hi);
        (order_at(mid) == runs.back().order ? lo : hi) = mid;
      }
      runs.back().z_hi = hi;
      runs.push_back({std::move(order), hi, std::numeric_limits<double>::infinity()});
    }
    // An order fits the line when each of its points, on the plane the order
    // gives its rank, lies in front of the camera at a depth where the order
    // holds (the surface across the line at about one depth, as the order
    // across the image assumes). A point's plane is the one every fitting
    // order gives its rank; none when no order fits.
    std::vector<int> plane(ranked.size(), -2);  // -2: no fitting order yet
    for (const Run& run : runs) {
      bool fits = true;
      for (size_t j = 0; j < ranked.size() && fits; ++j) {
        const Ranked& r = ranked[j];
        const Plane& sheet = planes[size_t(run.order[size_t(r.rank)])];
        const double z = -sheet.d / sheet.n.dot(r.ray) * r.ray.z();
        fits = std::isfinite(z) && z > 0 && z >= run.z_lo && z < run.z_hi;
      }
      if (!fits) continue;
      for (size_t j = 0; j < ranked.size(); ++j) {
        const Ranked& r = ranked[j];
        const int k = run.order[size_t(r.rank)];
        plane[j] = plane[j] == -2 || plane[j] == k ? k : -1;
        // Another sheet within kMergedPx of the point at its depth: the
        // stripe is both sheets' light, and which one it is is not known.
        const Plane& sheet = planes[size_t(k)];
        const double z = -sheet.d / sheet.n.dot(r.ray) * r.ray.z();
        const double x = r.ray.x() / r.ray.z(), y = r.ray.y() / r.ray.z(), here = rows ? x : y;
        for (size_t q = 0; q < planes.size(); ++q) {
          if (int(q) != k && std::abs(PositionAcross(planes[q], rows, x, y, z) - here) * focal < kMergedPx) plane[j] = -1;
        }
      }
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

}  // namespace lt

#include "pipeline/coverage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "core/error.h"
#include "core/random.h"

namespace lt {

namespace {

constexpr uint64_t kCoveragePurpose = 0x434f564552414745ull;  // "COVERAGE"

// Points bucketed in cubes of side `cell`.
class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3d>& points, double cell) : points_(points), cell_(cell) {
    for (size_t i = 0; i < points.size(); ++i) cells_[Key(Cell(points[i]))].push_back(i);
  }
  // Calls f(index) for every point in the 27 cells around p.
  template <typename F>
  void ForNear(const Eigen::Vector3d& p, F&& f) const {
    const Eigen::Vector3i c = Cell(p);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          auto it = cells_.find(Key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (size_t i : it->second) f(i);
        }
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const {
    return (p / cell_).array().floor().cast<int>();
  }
  static uint64_t Key(const Eigen::Vector3i& c) {
    return (uint64_t(uint32_t(c.x()) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y()) & 0x1fffff) << 21) |
           uint64_t(uint32_t(c.z()) & 0x1fffff);
  }
  const std::vector<Eigen::Vector3d>& points_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<size_t>> cells_;
};

}  // namespace

void CoverageOptions::Check() const {
  if (!(std::isfinite(distance_m) && distance_m > 0)) throw InputError("option distance", "must be > 0");
  if (!(std::isfinite(sample_spacing_m) && sample_spacing_m > 0)) throw InputError("option sample spacing", "must be > 0");
}

CoverageStats SurfaceCoverage(const std::vector<Triangle3d>& triangles, const std::vector<Eigen::Vector3d>& points,
                              const CoverageOptions& options,
                              const std::function<double(const Eigen::Vector3d&)>& laid_at,
                              const std::vector<double>& point_times) {
  options.Check();
  if (laid_at && point_times.size() != points.size()) {
    throw std::invalid_argument("SurfaceCoverage: " + std::to_string(point_times.size()) + " times for " +
                                std::to_string(points.size()) + " points");
  }
  CoverageStats s;
  const PointGrid grid(points, options.distance_m);
  const double d2 = options.distance_m * options.distance_m;
  const double a0 = options.sample_spacing_m * options.sample_spacing_m;
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Triangle3d& tri = triangles[t];
    const double area = 0.5 * (tri[1] - tri[0]).cross(tri[2] - tri[0]).norm();
    if (!(area > 0)) continue;
    s.area_m2 += area;
    const size_t n = std::max<size_t>(1, size_t(std::ceil(area / a0)));
    size_t hit = 0;
    for (size_t k = 0; k < n; ++k) {
      Rng rng = Rng::For(options.seed, t, k, 0, kCoveragePurpose);
      // Uniform on the triangle: sqrt-warped barycentrics.
      const double r1 = std::sqrt(rng.NextDouble()), r2 = rng.NextDouble();
      const Eigen::Vector3d p = (1 - r1) * tri[0] + r1 * (1 - r2) * tri[1] + r1 * r2 * tri[2];
      const double t_laid = laid_at ? laid_at(p) : 0.0;
      bool covered = false;
      grid.ForNear(p, [&](size_t i) {
        covered = covered || ((points[i] - p).squaredNorm() <= d2 && (!laid_at || point_times[i] >= t_laid));
      });
      hit += covered;
    }
    s.covered_m2 += area * double(hit) / double(n);
    s.samples += n;
  }
  return s;
}

struct LayingTimes::Grid {
  PointGrid points;
};

LayingTimes::LayingTimes(std::vector<Eigen::Vector3d> nozzle, std::vector<double> times, double radius_m)
    : nozzle_(std::move(nozzle)), times_(std::move(times)), radius_m_(radius_m) {
  if (nozzle_.size() != times_.size()) throw std::invalid_argument("LayingTimes: as many times as positions needed");
  if (!(radius_m_ > 0)) throw std::invalid_argument("LayingTimes: the radius must be > 0");
  grid_ = std::make_unique<Grid>(Grid{PointGrid(nozzle_, radius_m_)});
}

LayingTimes::~LayingTimes() = default;

double LayingTimes::At(const Eigen::Vector3d& p) const {
  // The nearest position; of equally near ones, the earliest.
  double best = std::numeric_limits<double>::infinity(), t = -std::numeric_limits<double>::infinity();
  grid_->points.ForNear(p, [&](size_t i) {
    const double d2 = (nozzle_[i] - p).squaredNorm();
    if (d2 > radius_m_ * radius_m_) return;
    if (d2 < best || (d2 == best && times_[i] < t)) best = d2, t = times_[i];
  });
  return t;
}

double MedianSpacingBetweenFrames(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& frames,
                                  double radius_m) {
  if (points.size() != frames.size()) throw std::invalid_argument("MedianSpacingBetweenFrames: size mismatch");
  const PointGrid grid(points, radius_m);
  std::vector<double> nearest;
  for (size_t i = 0; i < points.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    grid.ForNear(points[i], [&](size_t j) {
      if (frames[j] != frames[i]) best = std::min(best, (points[j] - points[i]).norm());
    });
    if (best <= radius_m) nearest.push_back(best);
  }
  if (nearest.empty()) return 0;
  std::nth_element(nearest.begin(), nearest.begin() + long(nearest.size() / 2), nearest.end());
  return nearest[nearest.size() / 2];
}

}  // namespace lt

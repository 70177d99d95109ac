// How well a scan covers a surface: the share of the surface's area within a
// sampling distance of a measured point, and the spacing of the measured points
// between frames (docs/experiments.md, "Coverage: scanner orientation").
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace lt {

using Triangle3d = std::array<Eigen::Vector3d, 3>;

struct CoverageOptions {
  double distance_m = 0.5e-3;         // a surface point is covered within this distance of a measured point
  double sample_spacing_m = 0.05e-3;  // about one surface sample per spacing^2 of area
  uint64_t seed = 0;                  // of the surface samples (Rng::For(seed, triangle, sample, ...))
  void Check() const;                 // throws lt::InputError
};

struct CoverageStats {
  double area_m2 = 0;          // of the triangles
  double covered_m2 = 0;       // estimated from the samples
  size_t samples = 0;
  double Share() const { return area_m2 > 0 ? covered_m2 / area_m2 : 0.0; }
};

// Samples the triangles uniformly by area (each triangle ceil(area / spacing^2)
// samples, at least one, each weighted by its share of the triangle's area) and
// counts the samples within `distance_m` of a point (a uniform grid of cell
// `distance_m` over the points).
// With `laid_at` (the time a surface point came to be, such as a bead's laying time,
// LayingTimes below) and `point_times` (one per point, the time it was measured), a
// sample counts as covered only by a point measured at or after the sample's time:
// a profile taken before the nozzle laid a bead measured what lay there before (the
// bed, the layer below, 0.2 mm under the bead's top), not the bead.
CoverageStats SurfaceCoverage(const std::vector<Triangle3d>& triangles, const std::vector<Eigen::Vector3d>& points,
                              const CoverageOptions& options,
                              const std::function<double(const Eigen::Vector3d&)>& laid_at = {},
                              const std::vector<double>& point_times = {});

// When each point of a printed bead was laid: the time of the nearest of the
// nozzle's positions along the path (sampled finely, each with its time) within
// `radius_m`; -infinity (laid before any sampled time) when none is that near.
class LayingTimes {
 public:
  // Throws std::invalid_argument when the sizes differ or radius_m is not > 0.
  LayingTimes(std::vector<Eigen::Vector3d> nozzle, std::vector<double> times, double radius_m);
  ~LayingTimes();
  LayingTimes(const LayingTimes&) = delete;  // the grid refers to the positions
  LayingTimes& operator=(const LayingTimes&) = delete;
  double At(const Eigen::Vector3d& p) const;

 private:
  struct Grid;
  std::vector<Eigen::Vector3d> nozzle_;
  std::vector<double> times_;
  double radius_m_;
  std::unique_ptr<Grid> grid_;
};

// The median, over the points, of the distance to the nearest point of another
// frame (the spacing of the profiles along the scan path); only neighbours within
// `radius_m` count; 0 when no point has one.
double MedianSpacingBetweenFrames(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& frames,
                                  double radius_m);

}  // namespace lt

// Coverage of a surface by measured points (pipeline/coverage.h) against closed
// forms, and the PLY reader (pipeline/scan_output.h) against the writer.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "core/error.h"
#include "pipeline/coverage.h"
#include "pipeline/scan_output.h"

namespace lt {
namespace {

// A 1 x 1 mm square in the z = 0 plane, as two triangles.
std::vector<Triangle3d> Square() {
  const Eigen::Vector3d a(0, 0, 0), b(1e-3, 0, 0), c(1e-3, 1e-3, 0), d(0, 1e-3, 0);
  return {{a, b, c}, {a, c, d}};
}

TEST(Coverage, StripAroundALineOfPoints) {
  // Points every 0.01 mm along x = 0.25 mm: within 0.1 mm of them lies the strip
  // 0.15 < x < 0.35 mm (its edges scalloped by at most 0.1 - sqrt(0.1^2 - 0.005^2)
  // = 0.000125 mm): 20% of the square.
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i <= 100; ++i) points.emplace_back(0.25e-3, i * 1e-5, 0);
  CoverageOptions o;
  o.distance_m = 0.1e-3;
  o.sample_spacing_m = 0.005e-3;
  const CoverageStats s = SurfaceCoverage(Square(), points, o);
  EXPECT_NEAR(s.area_m2, 1e-6, 1e-18);
  EXPECT_GE(s.samples, 40000u);
  // 40 000 independent uniform samples: the share's standard deviation is
  // sqrt(0.2 * 0.8 / 40000) = 0.002; 5 sigma.
  EXPECT_NEAR(s.Share(), 0.2, 0.01);
  // The same with the points 0.05 mm above the surface: the strip narrows to
  // 2 sqrt(0.1^2 - 0.05^2) = 0.1732 mm.
  for (auto& p : points) p.z() = 0.05e-3;
  EXPECT_NEAR(SurfaceCoverage(Square(), points, o).Share(), 0.1732, 0.01);
  // No points: nothing covered; deterministic for a given seed.
  EXPECT_EQ(SurfaceCoverage(Square(), {}, o).covered_m2, 0.0);
  EXPECT_EQ(SurfaceCoverage(Square(), points, o).covered_m2, SurfaceCoverage(Square(), points, o).covered_m2);
  o.distance_m = 0;
  EXPECT_THROW(SurfaceCoverage(Square(), points, o), InputError);
}

TEST(Coverage, PointsMeasuredBeforeTheSurfaceWasLaidDoNotCoverIt) {
  // A bead's top, the square, laid by a nozzle running along y = 0.5 mm from x = 0
  // (t = 0 s) to x = 1 mm (t = 1 s), 0.2 mm above the square's plane. Every point
  // lies 0.2 mm below the top (the layer under the bead, or the bed), within 0.25 mm
  // of all of it: measured at t = 2 s, after the nozzle passed, the whole top is
  // covered; measured at t = 0.5 s only the half laid by then (x < 0.5 mm).
  // Before, the points' times were not looked at: a profile taken ahead of the
  // nozzle, of what lay under the bead to come, covered it all.
  std::vector<Eigen::Vector3d> points, nozzle;
  std::vector<double> nozzle_times;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) points.emplace_back(i * 0.05e-3, j * 0.05e-3, -0.2e-3);
  for (int i = 0; i <= 100; ++i) {
    nozzle.emplace_back(i * 0.01e-3, 0.5e-3, 0.2e-3);
    nozzle_times.push_back(i * 0.01);
  }
  const LayingTimes laid(nozzle, nozzle_times, 1.5e-3);
  EXPECT_NEAR(laid.At({0.303e-3, 0.9e-3, 0}), 0.30, 1e-12);  // the nearest position's time
  EXPECT_EQ(laid.At({5e-3, 0.5e-3, 0}), -std::numeric_limits<double>::infinity());  // none within 1.5 mm
  const auto laid_at = [&](const Eigen::Vector3d& p) { return laid.At(p); };
  CoverageOptions o;
  o.distance_m = 0.25e-3;
  o.sample_spacing_m = 0.01e-3;
  EXPECT_NEAR(SurfaceCoverage(Square(), points, o).Share(), 1.0, 1e-12);  // times not given
  EXPECT_NEAR(SurfaceCoverage(Square(), points, o, laid_at, std::vector<double>(points.size(), 2.0)).Share(), 1.0,
              1e-12);
  // 10 000 samples: the share's standard deviation is 0.005; 4 sigma.
  EXPECT_NEAR(SurfaceCoverage(Square(), points, o, laid_at, std::vector<double>(points.size(), 0.5)).Share(), 0.5,
              0.02);
  EXPECT_EQ(SurfaceCoverage(Square(), points, o, laid_at, std::vector<double>(points.size(), -1.0)).covered_m2, 0.0);
  EXPECT_THROW(SurfaceCoverage(Square(), points, o, laid_at, {1.0}), std::invalid_argument);
}

TEST(Coverage, SpacingBetweenFrames) {
  // Frame k measures the line x = 0.3k mm: the nearest point of another frame is
  // 0.3 mm away, whatever the spacing within a frame (0.01 mm).
  std::vector<Eigen::Vector3d> points;
  std::vector<int> frames;
  for (int k = 0; k < 5; ++k)
    for (int i = 0; i < 50; ++i) {
      points.emplace_back(0.3e-3 * k, i * 1e-5, 0);
      frames.push_back(k);
    }
  EXPECT_NEAR(MedianSpacingBetweenFrames(points, frames, 1e-3), 0.3e-3, 1e-12);
  EXPECT_EQ(MedianSpacingBetweenFrames(points, frames, 0.2e-3), 0.0);  // no neighbour within 0.2 mm
}

TEST(ScanOutput, PlyReadsWhatItWrites) {
  const auto path = std::filesystem::temp_directory_path() / ("lt_ply_" + std::to_string(::getpid()) + ".ply");
  for (int variant = 0; variant < 4; ++variant) {
    PointCloud cloud;
    cloud.has_label = variant & 1;
    cloud.has_colour = variant & 2;
    cloud.points.push_back({{1.5, -2.25, 0.125}, 3, 1, {10, 20, 30}, 7});
    cloud.points.push_back({{0.001, 0.002, 0.003}, 5, 0, {255, 0, 1}, -1});
    WritePly(path, cloud);
    const PointCloud back = ReadPly(path);
    EXPECT_EQ(back.has_label, cloud.has_label);
    EXPECT_EQ(back.has_colour, cloud.has_colour);
    EXPECT_TRUE(back.world_frame);
    ASSERT_EQ(back.points.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(back.points[i].p, cloud.points[i].p);
      EXPECT_EQ(back.points[i].frame, cloud.points[i].frame);
      EXPECT_EQ(back.points[i].plane, cloud.points[i].plane);
      EXPECT_EQ(back.points[i].label, cloud.has_label ? cloud.points[i].label : -1);
      if (cloud.has_colour) {
        EXPECT_EQ(back.points[i].rgb, cloud.points[i].rgb);
      }
    }
  }
  // A truncated file is an error naming it.
  const std::string bytes = FormatPly(PointCloud{{{{1, 2, 3}, 0, 0, {0, 0, 0}, -1}}, false, false, true});
  std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() - 4);
  EXPECT_THROW(ReadPly(path), InputError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace lt

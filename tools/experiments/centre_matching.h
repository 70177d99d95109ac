// Stripe centres of a frame read from a run folder's CSV files, and the
// matching of measured centres to the renderer's exact ones, for the
// experiment programs (docs/experiments.md).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

namespace lt {

struct FrameCentre {
  int line = 0;      // scan line: the column for column search (gt_axis cols), else the row
  double pos = 0;    // subpixel position along the line
  int plane = -1;    // laser plane (-1: none)
  Eigen::Vector3d p_world = Eigen::Vector3d::Constant(NAN);  // NaN when not triangulated
};

// gt/NNNNNN_centers.csv or centers/NNNNNN.csv (columns u, v, plane and, when
// present, x_world, y_world, z_world).
std::vector<FrameCentre> ReadFrameCentres(const std::filesystem::path& csv, bool column_lines);

// For each measured centre, the index of the truth centre on the same scan
// line nearest to it along the line, if within max_distance_px; else -1.
std::vector<int> MatchToTruth(const std::vector<FrameCentre>& measured, const std::vector<FrameCentre>& truth,
                              double max_distance_px);

}  // namespace lt

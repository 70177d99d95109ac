// The scan's point cloud (cloud.ply) from the triangulated points of every
// laser frame: in the world frame when every frame has a pose, else in the
// camera frame; labelled with the ground truth's instance ids when every frame
// has them; coloured from the bright frames (pipeline/colorize.h) when the run
// has posed ones. Part of ScanRun (pipeline/scan.h).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "pipeline/colorize.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan.h"
#include "pipeline/scan_output.h"

namespace lt {

// What a cloud point needs until the cloud's frame (world or camera) is known.
struct PendingPoint {
  Eigen::Vector3d p_cam, p_world;
  bool has_world;
  int frame, plane;
  int label;
};

// The cloud of the pending points (in frame order). Warns about tool poses
// without camera poses and about frames without a pose; sets summary's colour
// statistics when the points are coloured.
PointCloud AssembleCloud(const std::vector<PendingPoint>& pending, const std::vector<RunFrame>& frames,
                         const Camera& camera, const RunRig& rig, const ColourOptions& colour, bool all_posed,
                         bool all_labelled, bool any_posed, ScanSummary* summary,
                         const std::function<void(const std::string&)>& warn);

}  // namespace lt

#include "pipeline/scan_cloud.h"

#include <algorithm>

namespace lt {

PointCloud AssembleCloud(const std::vector<PendingPoint>& pending, const std::vector<RunFrame>& frames,
                         const Camera& camera, const RunRig& rig, const ColourOptions& colour, bool all_posed,
                         bool all_labelled, bool any_posed, ScanSummary* summary,
                         const std::function<void(const std::string&)>& warn) {
  PointCloud cloud;
  cloud.world_frame = all_posed;
  if (!any_posed && std::any_of(frames.begin(), frames.end(), [](const RunFrame& f) { return f.world_from_tool.has_value(); })) {
    warn("the frames have tool poses (world_from_tool) but no camera poses: a calibration file with the hand-eye "
         "pose (tool_from_cam, --calib) places the cloud in the world frame");
  }
  if (!all_posed && any_posed) warn("some frames have no pose (" + summary->pose_source + "): cloud.ply is in the camera frame");
  cloud.points.reserve(pending.size());
  cloud.has_label = all_labelled;
  for (const PendingPoint& p : pending) {
    if (all_posed && !p.has_world) continue;  // cannot happen: a posed frame's points all have world coordinates
    cloud.points.push_back({all_posed ? p.p_world : p.p_cam, p.frame, p.plane, {0, 0, 0}, p.label});
  }
  // Colour from the bright frames next to each laser frame (world frame only).
  const bool has_bright = std::any_of(frames.begin(), frames.end(), [](const RunFrame& f) {
    return f.IsColourFrame() && f.world_from_cam.has_value();
  });
  if (all_posed && has_bright && !cloud.points.empty()) {
    Colorizer colorizer(frames, camera, rig.color_filter, rig.black_level_dn, colour);
    for (size_t begin = 0; begin < cloud.points.size();) {
      size_t end = begin;
      std::vector<Eigen::Vector3d> world;
      while (end < cloud.points.size() && cloud.points[end].frame == cloud.points[begin].frame) {
        world.push_back(cloud.points[end++].p);
      }
      const std::vector<PointColour> colours = colorizer.Colour(cloud.points[begin].frame, world);
      for (size_t k = begin; k < end; ++k) cloud.points[k].rgb = colours[k - begin].rgb;
      begin = end;
    }
    cloud.has_colour = true;
    summary->colour = colorizer.stats();
    summary->coloured = true;
  }
  return cloud;
}

}  // namespace lt

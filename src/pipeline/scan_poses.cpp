#include "pipeline/scan_poses.h"

#include <algorithm>

#include "core/error.h"

namespace lt {

std::string GivePoses(const PoseFile& poses, const std::filesystem::path& file, bool as_tool,
                      std::vector<RunFrame>* frames, const std::string& frames_source) {
  if (poses.poses.size() != frames->size()) {
    throw InputError(file.string(), "holds " + std::to_string(poses.poses.size()) + " pose" +
                                        (poses.poses.size() == 1 ? "" : "s") + " but " + frames_source + " has " +
                                        std::to_string(frames->size()) + " frame" + (frames->size() == 1 ? "" : "s") +
                                        " (one pose per frame, in frame order)");
  }
  for (size_t k = 0; k < frames->size(); ++k) {
    RunFrame& f = (*frames)[k];
    (as_tool ? f.world_from_tool : f.world_from_cam) = poses.poses[k];
  }
  return std::string(as_tool ? "world_from_tool" : "world_from_cam") + " from " + file.string() + " (" + poses.form +
         (poses.units == PoseUnits::kMillimetres ? ", mm" : ", m") + ")";
}

std::string ResolveScanPoses(const std::optional<std::filesystem::path>& pose_file, const PoseFileOptions& options,
                             const std::optional<Pose>& tool_from_cam,
                             const std::optional<std::filesystem::path>& calibration, const std::string& frames_source,
                             std::vector<RunFrame>* frames, const std::function<void(const std::string&)>& warn) {
  std::string source = "world_from_cam", tool_source = "world_from_tool";
  if (pose_file) {
    const PoseFile poses = ReadPoseFile(*pose_file, options, warn);
    source = GivePoses(poses, *pose_file, tool_from_cam.has_value(), frames, frames_source);
    tool_source = source;
  }
  if (!tool_from_cam) return source;
  // As a real scanner on a robot or printer knows its pose: world_from_cam = world_from_tool · tool_from_cam.
  const std::string calibration_name = calibration ? calibration->string() : std::string("the calibration");
  if (std::none_of(frames->begin(), frames->end(), [](const RunFrame& f) { return f.world_from_tool.has_value(); })) {
    if (warn) warn(calibration_name + ": tool_from_cam is not used: the run's frames have no world_from_tool");
    return source;
  }
  for (RunFrame& f : *frames) {
    f.world_from_cam = f.world_from_tool ? std::optional<Pose>(*f.world_from_tool * *tool_from_cam) : std::nullopt;
  }
  return tool_source + " · tool_from_cam of " + calibration_name;
}

}  // namespace lt

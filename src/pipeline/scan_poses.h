// The camera poses a scan stitches its cloud with (docs/pipeline.md, "Poses
// from a file" and "Calibration file"): the manifest's world_from_cam, or a
// pose file's (--poses), or, with a calibration file's hand-eye pose
// tool_from_cam, world_from_tool · tool_from_cam from the manifest's or the
// pose file's tool poses.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"
#include "pipeline/pose_file.h"
#include "pipeline/run_folder_reader.h"

namespace lt {

// Gives frame k (in order) the pose file's pose k: as world_from_tool when
// `as_tool` (a hand-eye calibration turns it into the camera's pose), else as
// world_from_cam. When the counts differ and the file has times (TUM, a time
// column) and every image is named by its time ("1305031102.175304.png", in s,
// or ms, us, ns) within the file's times, frame k takes the pose interpolated
// at its image's time (core/pose_trajectory.h; the times must increase);
// otherwise throws lt::InputError naming the file and both counts. With
// `image_time_offset_s`, every frame is matched by time, at its name's time
// plus the offset (a camera stamping the start of its exposure: half the
// exposure), whatever the counts; names that are not times within the file's
// then throw. Returns what the poses are ("world_from_cam from FILE (TUM, m)").
std::string GivePoses(const PoseFile& poses, const std::filesystem::path& file, bool as_tool,
                      std::vector<RunFrame>* frames, const std::string& frames_source,
                      std::optional<double> image_time_offset_s = std::nullopt);

// Sets each frame's world_from_cam as above: reads `pose_file` (when given; the
// tool's poses when `tool_from_cam` is given, else the camera's), then chains
// the tool poses with tool_from_cam (from `calibration`): a frame without a tool
// pose then has no camera pose; frames without any tool pose keep their
// world_from_cam (warned). Returns the poses' source for the summary.
std::string ResolveScanPoses(const std::optional<std::filesystem::path>& pose_file, const PoseFileOptions& options,
                             const std::optional<Pose>& tool_from_cam,
                             const std::optional<std::filesystem::path>& calibration, const std::string& frames_source,
                             std::vector<RunFrame>* frames, const std::function<void(const std::string&)>& warn);

}  // namespace lt

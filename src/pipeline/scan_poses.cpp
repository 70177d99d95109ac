#include "pipeline/scan_poses.h"

#include <algorithm>

#include "core/error.h"
#include "core/pose_trajectory.h"
#include "core/text_fields.h"

namespace lt {

namespace {

// The poses at the times the images' names give ("1305031102.175304.png"), in
// seconds or, when those fall outside the pose file's times, ms, us or ns,
// plus offset_s; nullopt unless every such time lies within the file's times.
std::optional<std::vector<Pose>> PosesAtImageTimes(const PoseFile& poses, const std::filesystem::path& file,
                                                   const std::vector<RunFrame>& frames, double offset_s) {
  if (poses.times_s.size() < 2 || poses.times_s.size() != poses.poses.size()) return std::nullopt;
  std::vector<double> names;
  for (const RunFrame& f : frames) {
    const auto t = ParseFiniteNumber(f.image.stem().string());
    if (!t) return std::nullopt;
    names.push_back(*t);
  }
  const double first = poses.times_s.front(), last = poses.times_s.back();
  for (const double to_s : {1.0, 1e-3, 1e-6, 1e-9}) {
    auto time_of = [&](double name) { return name * to_s + offset_s; };
    if (!std::all_of(names.begin(), names.end(), [&](double t) { return time_of(t) >= first && time_of(t) <= last; }))
      continue;
    std::vector<PoseSample> samples;
    for (size_t k = 0; k < poses.poses.size(); ++k) {
      if (k > 0 && !(poses.times_s[k] > poses.times_s[k - 1])) {
        throw InputError(file.string() + ":" + std::to_string(poses.lines[k]),
                         "time " + FormatNumber(poses.times_s[k]) + " s does not increase (previous pose at " +
                             FormatNumber(poses.times_s[k - 1]) + " s): poses matched to the images' times need "
                             "increasing times");
      }
      samples.push_back({poses.times_s[k], poses.poses[k].translation(), Eigen::Quaterniond(poses.poses[k].linear())});
    }
    const PoseTrajectory trajectory(std::move(samples));
    std::vector<Pose> out;
    for (const double t : names) out.push_back(trajectory.At(time_of(t)));
    return out;
  }
  return std::nullopt;
}

// Whether the images' names are frame numbers rather than times: all digits,
// one of them zero-padded ("000000.png", as renderers and frame grabbers
// number frames). A clock's time is not written with leading zeros, and read as
// milliseconds such numbers fall within any log starting near 0.
bool NamesAreFrameNumbers(const std::vector<RunFrame>& frames) {
  bool padded = false;
  for (const RunFrame& f : frames) {
    const std::string stem = f.image.stem().string();
    if (stem.empty() || !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return false;
    padded = padded || (stem.size() > 1 && stem[0] == '0');
  }
  return padded;
}

}  // namespace

std::string GivePoses(const PoseFile& poses, const std::filesystem::path& file, bool as_tool,
                      std::vector<RunFrame>* frames, const std::string& frames_source,
                      std::optional<double> image_time_offset_s) {
  std::vector<Pose> chosen = poses.poses;
  std::string how;
  if (image_time_offset_s) {
    std::optional<std::vector<Pose>> at_times = PosesAtImageTimes(poses, file, *frames, *image_time_offset_s);
    if (!at_times) {
      throw InputError(file.string(), "--image-time-offset matches poses to the images' times, but " +
                                          (poses.times_s.size() < 2 ? std::string("the file has no times")
                                                                    : frames_source +
                                                                          "'s image names are not all times within "
                                                                          "the file's, " +
                                                                          FormatNumber(poses.times_s.front()) + " to " +
                                                                          FormatNumber(poses.times_s.back()) +
                                                                          " s, once shifted by the offset"));
    }
    chosen = std::move(*at_times);
    how = ", interpolated at the images' times + " + FormatNumber(*image_time_offset_s) + " s";
  } else if (poses.poses.size() != frames->size()) {
    // More (or fewer) poses than frames: a tracker's log at its own rate, matched by the images' times.
    std::optional<std::vector<Pose>> at_times;
    if (!NamesAreFrameNumbers(*frames)) at_times = PosesAtImageTimes(poses, file, *frames, 0.0);
    if (!at_times) {
      throw InputError(file.string(), "holds " + std::to_string(poses.poses.size()) + " pose" +
                                          (poses.poses.size() == 1 ? "" : "s") + " but " + frames_source + " has " +
                                          std::to_string(frames->size()) + " frame" + (frames->size() == 1 ? "" : "s") +
                                          " (one pose per frame, in frame order; or poses with times and images "
                                          "named by their time within them)");
    }
    chosen = std::move(*at_times);
    how = ", interpolated at the images' times";
  }
  for (size_t k = 0; k < frames->size(); ++k) {
    RunFrame& f = (*frames)[k];
    (as_tool ? f.world_from_tool : f.world_from_cam) = chosen[k];
  }
  return std::string(as_tool ? "world_from_tool" : "world_from_cam") + " from " + file.string() + " (" + poses.form +
         (poses.units == PoseUnits::kMillimetres ? ", mm" : ", m") + how + ")";
}

std::string ResolveScanPoses(const std::optional<std::filesystem::path>& pose_file, const PoseFileOptions& options,
                             const std::optional<Pose>& tool_from_cam,
                             const std::optional<std::filesystem::path>& calibration, const std::string& frames_source,
                             std::vector<RunFrame>* frames, const std::function<void(const std::string&)>& warn) {
  std::string source = "world_from_cam", tool_source = "world_from_tool";
  if (pose_file) {
    const PoseFile poses = ReadPoseFile(*pose_file, options, warn);
    source = GivePoses(poses, *pose_file, tool_from_cam.has_value(), frames, frames_source, options.image_time_offset_s);
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

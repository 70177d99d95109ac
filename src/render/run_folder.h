// A run folder, as `lasertwin render` writes it:
//   frames/NNNNNN.png        camera images as the camera delivers them
//   radiance/NNNNNN.exr      linear radiance (broadband RGB and laser)
//   gt/NNNNNN.exr            ground-truth buffers; gt/NNNNNN_centers.csv stripe centres
//   manifest.jsonl           one JSON line per completed frame, sorted by index
//   scene.json               the resolved scene, so the run can be reproduced
// Every file is written under a temporary name and renamed. A frame counts as
// complete only when its manifest line exists, and that line is written after
// all of the frame's files, so an interrupted run never shows a half frame as done.
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace lt {

class RunFolder {
 public:
  // Opens `dir` for writing. A folder that already holds a manifest or scene.json
  // is refused unless `resume` (so nothing already written is lost); with
  // `resume`, its scene.json must equal `resolved_scene`.
  RunFolder(const std::filesystem::path& dir, const nlohmann::json& resolved_scene, bool resume);

  const std::filesystem::path& dir() const { return dir_; }
  // Relative file names of one frame ("frames/000012.png", ...).
  static std::string FrameImageName(int index);
  static std::string RadianceName(int index);
  static std::string GroundTruthName(int index);
  static std::string CentersName(int index);

  bool IsComplete(int index) const { return manifest_.count(index) != 0; }
  // Records a completed frame: rewrites manifest.jsonl atomically with the line added.
  void CompleteFrame(int index, const nlohmann::json& line);
  const std::map<int, nlohmann::json>& manifest() const { return manifest_; }

  // Reads manifest.jsonl of an existing run (for scan/eval). Errors name file:line.
  static std::map<int, nlohmann::json> ReadManifest(const std::filesystem::path& dir);

 private:
  std::filesystem::path dir_;
  std::map<int, nlohmann::json> manifest_;
};

}  // namespace lt

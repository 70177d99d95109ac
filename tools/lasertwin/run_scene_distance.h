// The distance from a run's measured points to the surfaces of its scene
// (RUN/scene.json), for the evaluation (pipeline/eval_metrics.h,
// docs/evaluation.md): `lasertwin eval` and `lasertwin sweep` score points with it.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/eval_metrics.h"

namespace lt::cli {

// The distance to the surfaces of RUN/scene.json at each frame's time (the
// printed part grown to the frame's mid-exposure, as the renderer grows it),
// for points in the frame's camera frame (the manifest's world_from_cam, else
// the scene's motion at mid-exposure). Empty without RUN/scene.json, or when it
// cannot be loaded (a run moved away from its glTF files): *why_not says why.
SurfaceDistanceSource RunSceneDistance(const std::filesystem::path& run_dir, std::string* why_not);

}  // namespace lt::cli

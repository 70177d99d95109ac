#include "tools/lasertwin/run_scene_distance.h"

#include <memory>

#include "core/error.h"
#include "scene/motion.h"
#include "scene/scene_file.h"
#include "scene/surface_distance.h"

namespace lt::cli {

SurfaceDistanceSource RunSceneDistance(const std::filesystem::path& run_dir, std::string* why_not) {
  const std::filesystem::path path = run_dir / "scene.json";
  if (!std::filesystem::exists(path)) {
    *why_not = path.string() + ": no such file (a recorded run): points are scored on the ground-truth buffers";
    return {};
  }
  std::shared_ptr<SceneFile> scene;
  std::shared_ptr<SceneSurface> surface;
  try {
    scene = std::make_shared<SceneFile>(LoadSceneFile(path));
    surface = std::make_shared<SceneSurface>(*scene);
  } catch (const InputError& e) {
    *why_not = std::string(e.what()) + " (the run's scene could not be loaded: points are scored on the "
                                       "ground-truth buffers)";
    return {};
  }
  return [scene, surface](const RunFrame& f) -> PointToSurface {
    const double t_mid = 0.5 * (f.t_start_s + f.t_end_s);
    surface->UpdateTo(t_mid);
    const Pose world_from_cam = f.world_from_cam ? *f.world_from_cam : WorldFromCamAt(scene->motion, t_mid);
    return [surface, world_from_cam](const Eigen::Vector3d& p_in_cam) {
      return surface->Distance(world_from_cam * p_in_cam);
    };
  };
}

}  // namespace lt::cli

// Reading a run's ground truth for evaluation (docs/run-folder.md, "Ground
// truth"), without the renderer: the exact stripe centres
// (gt/NNNNNN_centers.csv) and the true surface under each pixel (gt/NNNNNN.exr:
// depth Z and normal N.X, N.Y, N.Z, camera frame).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "core/image.h"
#include "sensor/camera.h"

namespace lt {

struct TruthCenter {
  double u = 0, v = 0;  // pixel (OpenCV convention)
  int plane = 0;        // global laser plane number
  Eigen::Vector3d p_in_cam = Eigen::Vector3d::Zero();  // metres
  int line = 0;         // line of the CSV file it was read from (0 when not read from a file)
};

// Reads gt/NNNNNN_centers.csv (header u,v,plane,x_cam,y_cam,z_cam,x_world,
// y_world,z_world; the world columns are not needed and may be empty).
// Errors: lt::InputError naming "file:line".
std::vector<TruthCenter> ReadTruthCentersCsv(const std::filesystem::path& path);

// The true surface seen by a camera, from the ground-truth buffers.
class TrueSurface {
 public:
  // Throws lt::InputError naming the file: unreadable, no Z / N.X / N.Y / N.Z
  // channels, or a size other than the camera's.
  TrueSurface(const Camera& camera, const std::filesystem::path& gt_exr);

  // Signed distance (metres) of p_in_cam to the true surface at the pixel p
  // projects to, positive on the camera's side: when the 4 pixels around the
  // projection lie on one surface, the bilinear blend of their distances along
  // the mean of each one's normal and p's (second-order exact on a curved
  // surface: 0 for a point of a sphere or cylinder), else
  // (a break: edge, step, silhouette) the smallest in magnitude of the tangent
  // planes' of the 3x3 pixels around the nearest one and of the distances to
  // `exact_points` (true surface points near p, such as the exact stripe centres
  // of its scan line and the lines beside it: a face narrower than a pixel that
  // no pixel centre sees still has them; positive when p is nearer the camera
  // along its ray) (see pipeline/eval_metrics.h). nullopt when p does not
  // project into the image or the nearest pixel sees nothing.
  std::optional<double> SignedDistance(const Eigen::Vector3d& p_in_cam,
                                       std::span<const Eigen::Vector3d> exact_points = {}) const;

 private:
  struct Texel {
    bool hit = false;
    double instance = -1;
    Eigen::Vector3d s = Eigen::Vector3d::Zero();  // surface point
    Eigen::Vector3d n = Eigen::Vector3d::Zero();  // unit normal
  };
  Texel At(int x, int y) const;  // computed on demand (one Unproject)

  Camera camera_;
  Image<float> buffers_;
  int z_ = 0, nx_ = 0, ny_ = 0, nz_ = 0, instance_ = -1;  // channels
};

}  // namespace lt

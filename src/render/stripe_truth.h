// Exact ground-truth stripe centres. For every image row (or column, when the
// stripes run horizontally) and every laser sheet: the subpixel position where
// the surface seen along that row lies exactly on the sheet's plane and is lit
// by it. Found by root finding on real ray casts through the camera model (with
// its distortion), not read off the rendered image:
//
//   g(u) = n·p(u) + d,  p(u) = first surface hit of the chief ray of pixel (u, v)
//
// is sampled at every pixel centre and at both image borders; each sign change
// between neighbouring samples on a continuous surface is refined by the
// Illinois method to |Δu| < 1e-6 px. A bracket whose ends stay apart (a depth
// discontinuity, not a crossing) is rejected, at once when it is narrower than
// 1e-4 px with its ends on two surfaces; ends on one plane (a surface seen
// edge-on) have converged however far apart. Between neighbouring samples on
// two surfaces (normals more than 30 degrees apart, one off the other's plane
// by more than a pixel's footprint, or a hit beside a miss) near a sheet, the
// line is bisected to each break and every surface is searched up to it: the
// sheet may cross a surface between its last pixel centre and its edge, or two
// surfaces within one pixel, without a sign change between the centres. Between
// neighbouring samples on one surface near a sheet with no sign change, the
// line is bisected toward every crease (facet normals apart) until a sample
// falls between a pair of crossings there, if any (a stripe turning back
// across the line, or crossing two facets, within one pixel); pairs closer
// than 1e-4 px are taken for a tangency. A root counts as lit when the
// surface faces both the camera and the projector, the segment to the projector
// is unoccluded, and the fan profile there is at least `fan_threshold` of its
// value on the sheet's central ray at the same distance.
//
// The pixel centres miss a surface that none of them sees and that lies wholly
// between two samples on one other surface (a thin fin nearly edge-on). So the
// candidates also come from the geometry (render/stripe_truth_segments.h):
// each sheet's plane cuts each triangle in a segment, projected through the
// camera model; each crossing of a scan line that no centre found above holds
// (within 1e-4 px) is decided by the same ray casts, refinement and lit test.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/pose.h"
#include "scene/embree_scene.h"
#include "sensor/camera.h"
#include "sensor/laser.h"

namespace lt {

enum class ScanAxis { kRows, kCols };
std::string ScanAxisName(ScanAxis axis);  // "rows" / "cols"

struct StripeCenter {
  double u = 0, v = 0;  // pixel coordinates (OpenCV)
  int plane = 0;        // global sheet index: sheets of laser 0 first, then laser 1, ...
  Eigen::Vector3d p_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
};

// The first hit of the chief ray through a pixel centre (world frame), as the
// renderer's ground-truth pass finds it; lets the search reuse those casts.
struct ChiefHit {
  bool valid = false;
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // geometric, world
  double depth = 0;                                  // distance along the ray, metres
  uint32_t material = 0;
};

struct StripeTruthOptions {
  double tolerance_px = 1e-6;   // bracket width at which refinement stops
  double fan_threshold = 0.01;  // minimum relative fan intensity to count as lit
  int max_iterations = 100;
  void Check() const;
};

// Rows when the stripes run mostly vertically in the image, columns otherwise
// (decided from the first sheet's plane: its image direction is (-n_y, n_x)).
ScanAxis ChooseScanAxis(const std::vector<LaserProjector>& lasers);

// Global plane index of (laser, sheet) and the total number of planes.
int GlobalPlaneIndex(const std::vector<LaserProjector>& lasers, int laser, int sheet);
int PlaneCount(const std::vector<LaserProjector>& lasers);

// All stripe centres of a frame, sorted by (scan line, plane, position). Rays
// start at the camera centre (chief rays; a thin lens focuses them unchanged).
// `pixel_hits` (optional, width x height, row-major) holds the chief-ray hits
// of the pixel centres for the same pose, which then are not cast again.
std::vector<StripeCenter> ComputeStripeCenters(const EmbreeScene& scene, const Camera& camera,
                                               const std::vector<LaserProjector>& lasers,
                                               const Pose& world_from_cam, ScanAxis axis,
                                               const StripeTruthOptions& options = {},
                                               const std::vector<ChiefHit>* pixel_hits = nullptr);

// CSV with header u,v,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world.
std::string StripeCentersCsv(const std::vector<StripeCenter>& centers);

}  // namespace lt

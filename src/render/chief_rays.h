// The chief rays of a block of pixels (FrameRenderer::GroundTruthPass): one
// ray a pixel, from the camera's origin through the pixel's centre, traced in
// coherent 4x4 packets (Embree's rtcIntersect16) and refined to the same hits
// as EmbreeScene::Intersect gives ray by ray.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "core/pose.h"
#include "scene/embree_scene.h"
#include "sensor/camera.h"

namespace lt {

struct ChiefRay {
  bool traced = false;                            // the pixel has a ray (cam.Unproject succeeded)
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // world frame, from world_from_cam's origin
  std::optional<Hit> hit;                         // embree.Intersect of that ray
};

// Fills rays[(y - y0) * (x1 - x0) + (x - x0)] for the pixels x0 <= x < x1,
// y0 <= y < y1 (rays.size() must be their count). Every hit is the one
// embree.Intersect returns for the pixel's ray: a packet's hit is refined by
// EmbreeScene::MakeHit from its triangle, and a lane whose triangle may not be
// the one the single ray finds (a hit within kEdgeBarycentric of a triangle's
// edge, where two triangles meet at the same distance and the traversal order
// decides) or whose refined hit lies at or behind the origin is traced again by
// embree.Intersect (as is every ray when Embree has no ray packets). Returns
// the number of rays (pixels with one). Thread-safe.
uint64_t TraceChiefRays(const EmbreeScene& embree, const Camera& cam, const Pose& world_from_cam, int x0, int y0, int x1,
                        int y1, std::span<ChiefRay> rays);

}  // namespace lt

// The scanner's lights placed in the world for one instant of a frame: the
// laser projectors and the pattern projector (monochromatic point emitters),
// and the LED flood light. Each carries the fraction of the exposure it was lit
// (from the shutter schedule), which weights its contribution, so the film
// accumulates radiance averaged over the exposure time.
#pragma once

#include <optional>
#include <vector>

#include "core/pose.h"
#include "sensor/rig.h"

namespace lt {

class LaserEntryTree;

// A monochromatic point emitter (a laser projector or the pattern projector).
struct PointEmitter {
  const LaserProjector* laser = nullptr;      // exactly one of these is set
  const PatternProjector* pattern = nullptr;
  Pose projector_from_world;
  Eigen::Vector3d origin_world;
  double wavelength_m = 0;
  int group = 0;          // index of this emitter (its own wavelength channel)
  int first_channel = 0;  // film channel of its sheet 0 (a pattern has one channel)
  int channels = 1;       // sheets (pattern: 1)
  double weight = 0;      // lit fraction of the exposure, 0..1
  // Per sheet, the frame's cache of lit entry points (render/laser_entry_tree.h),
  // or null: subsurface light then comes from Monte Carlo. Empty: none.
  std::vector<const LaserEntryTree*> entry_trees;
  // Sets projector_from_world and origin_world for the camera pose
  // world_from_cam (PlaceProjector); laser or pattern must be set.
  void Place(const Pose& world_from_cam);
};

// Where a point emitter's projector is for a camera pose.
struct ProjectorPlacement {
  Pose projector_from_world;
  Eigen::Vector3d origin_world;
};
// Emitter e's projector (its laser's or pattern's cam_from_projector) placed
// for the camera pose world_from_cam.
ProjectorPlacement PlaceProjector(const PointEmitter& e, const Pose& world_from_cam);

struct LedLight {
  const Led* led = nullptr;
  Pose world_from_cam;  // the LED's own pose is led->cam_from_led()
  Pose world_from_led;
  double weight = 0;
};

// The film channel layout of a rig: laser sheets in laser order, then the pattern.
struct EmitterLayout {
  int channels = 0;        // film laser channels
  int laser_sheets = 0;    // of which laser sheets (global plane index = channel)
  int groups = 0;          // emitters
  std::vector<double> group_wavelength_m;
};
EmitterLayout MakeEmitterLayout(const SensorRig& rig);

struct FrameLights {
  std::vector<PointEmitter> emitters;  // only those lit during the exposure
  std::optional<LedLight> led;         // only when lit during the exposure
  int groups = 0;
  // Laser light reflected on from grazing incidence is carried by light paths
  // (PathTracer::TraceLightPaths), which camera paths then leave out.
  bool grazing_by_light_paths = false;
  // A moving frame's caches by time slice (FrameRenderer::Render): the exposure
  // cut into entry_tree_slices.size() equal parts, each holding, per emitter and
  // sheet, the caches built at the pose of its middle; a camera sample at time t
  // takes those of the part holding t. Empty: each emitter's entry_trees serve
  // the whole exposure.
  std::vector<std::vector<std::vector<const LaserEntryTree*>>> entry_tree_slices;  // [slice][emitter][sheet]
};

// Emitter e (of MakeFrameLights) placed for the camera pose world_from_cam.
PointEmitter EmitterAt(const PointEmitter& e, const Pose& world_from_cam);

// Lights at the camera pose world_from_cam, weighted by the lit fractions of the
// frame (laser_fraction, pattern_fraction, led_fraction).
FrameLights MakeFrameLights(const SensorRig& rig, const Pose& world_from_cam, double laser_fraction,
                            double pattern_fraction, double led_fraction);

}  // namespace lt

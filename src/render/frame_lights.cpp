#include "render/frame_lights.h"

#include <stdexcept>
#include <string>

namespace lt {

EmitterLayout MakeEmitterLayout(const SensorRig& rig) {
  EmitterLayout layout;
  for (const auto& laser : rig.lasers) {
    layout.channels += laser.sheet_count();
    layout.group_wavelength_m.push_back(laser.wavelength_m());
  }
  layout.laser_sheets = layout.channels;
  if (rig.pattern) {
    layout.channels += 1;
    layout.group_wavelength_m.push_back(rig.pattern->wavelength_m());
  }
  layout.groups = int(layout.group_wavelength_m.size());
  if (layout.groups > kMaxRigEmitters || layout.channels > kMaxRigSheets) {
    throw std::invalid_argument("a rig holds at most " + std::to_string(kMaxRigEmitters) +
                                " lasers and pattern projectors and " + std::to_string(kMaxRigSheets) +
                                " sheets; this one has " + std::to_string(layout.groups) + " and " +
                                std::to_string(layout.channels));
  }
  return layout;
}

ProjectorPlacement PlaceProjector(const PointEmitter& e, const Pose& world_from_cam) {
  const Pose world_from_projector =
      world_from_cam * (e.laser ? e.laser->cam_from_projector() : e.pattern->cam_from_projector());
  return {world_from_projector.inverse(), world_from_projector.translation()};
}

void PointEmitter::Place(const Pose& world_from_cam) {
  const ProjectorPlacement p = PlaceProjector(*this, world_from_cam);
  projector_from_world = p.projector_from_world;
  origin_world = p.origin_world;
}

PointEmitter EmitterAt(const PointEmitter& e, const Pose& world_from_cam) {
  PointEmitter placed = e;
  placed.Place(world_from_cam);
  return placed;
}

FrameLights MakeFrameLights(const SensorRig& rig, const Pose& world_from_cam, double laser_fraction,
                            double pattern_fraction, double led_fraction) {
  FrameLights lights;
  int channel = 0, group = 0;
  for (const auto& laser : rig.lasers) {
    if (laser_fraction > 0 && laser.power_w() > 0) {
      PointEmitter e;
      e.laser = &laser;
      e.Place(world_from_cam);
      e.wavelength_m = laser.wavelength_m();
      e.group = group;
      e.first_channel = channel;
      e.channels = laser.sheet_count();
      e.weight = laser_fraction;
      lights.emitters.push_back(e);
    }
    channel += laser.sheet_count();
    ++group;
  }
  if (rig.pattern) {
    if (pattern_fraction > 0 && rig.pattern->power_w() > 0) {
      PointEmitter e;
      e.pattern = &*rig.pattern;
      e.Place(world_from_cam);
      e.wavelength_m = rig.pattern->wavelength_m();
      e.group = group;
      e.first_channel = channel;
      e.channels = 1;
      e.weight = pattern_fraction;
      lights.emitters.push_back(e);
    }
    ++group;
  }
  lights.groups = group;
  if (rig.led && led_fraction > 0) {
    lights.led = LedLight{&*rig.led, world_from_cam, world_from_cam * rig.led->cam_from_led(), led_fraction};
  }
  return lights;
}

}  // namespace lt

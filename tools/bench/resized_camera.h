// The benchmarks' frames at other resolutions than their scenes': the scene's
// camera over the same field of view, with larger (or smaller) pixels.
#pragma once

#include "sensor/camera.h"

namespace lt {

// `camera` at width x height: focal lengths in pixels and the pixel pitch scaled
// by width / camera.width(), the principal point at the image centre.
inline Camera ResizedCamera(const Camera& camera, int width, int height) {
  CameraParams p = camera.params();
  const double s = double(width) / p.width;
  p.fx *= s, p.fy *= s;
  p.pixel_pitch_m /= s;
  p.cx = (width - 1) / 2.0, p.cy = (height - 1) / 2.0;
  p.width = width, p.height = height;
  return Camera(p);
}

}  // namespace lt

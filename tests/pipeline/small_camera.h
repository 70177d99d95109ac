// The camera of the plane-numbering tests: 160 x 120 pixels, pinhole, f = 200 px,
// principal point at the image's centre (79.5, 59.5).
#pragma once

#include "sensor/camera.h"

namespace lt::test {

inline Camera SmallCamera() {
  CameraParams c;
  c.width = 160, c.height = 120;
  c.fx = c.fy = 200;
  c.cx = 79.5, c.cy = 59.5;
  return Camera(c);
}

}  // namespace lt::test

// A laser stripe centre found in an image, and the pixel rectangle type used
// for regions of interest.
#pragma once

namespace lt {

// One stripe centre. (u, v) are pixel coordinates in the OpenCV convention
// (u right, v down, centre of pixel (0,0) at (0,0)) of the whole image, not of
// the ROI. When searching along rows, v is the (integer) row and u the subpixel
// column where the stripe's centre line crosses that row; along columns the
// roles swap. `width` is the stripe's full width at half maximum in pixels and
// `strength` the value the method compared with its threshold (see
// docs/extraction.md). `plane` is the laser plane index after plane
// identification, -1 when unknown.
struct StripePoint {
  double u = 0;
  double v = 0;
  double width = 0;
  double strength = 0;
  int plane = -1;
};

// A rectangle of pixels: columns [x, x + width), rows [y, y + height).
struct PixelRect {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
};

}  // namespace lt

// Bilinear demosaicing of raw Bayer mosaics (the raw frames of a colour sensor)
// into three colour planes, so that stripe extraction sees a smooth stripe
// instead of the mosaic's alternating filter gains (docs/extraction.md, "Bayer
// mosaics").
#pragma once

#include <string>
#include <vector>

#include "core/image.h"
#include "sensor/image_sensor.h"

namespace lt {

// "none" (or "mono"), "rggb", "bggr", "grbg", "gbrg"; anything else is an
// lt::InputError(where, ...).
ColorFilter ParseBayerPattern(const std::string& text, const std::string& where);
const char* BayerPatternName(ColorFilter filter);  // "none", "rggb", ...

// Demosaics the one-channel mosaic `mosaic` (filter `filter`, not kMono) into
// `rgb`: width x height x 3 floats, interleaved R, G, B. (phase_x, phase_y) is
// the position of the view's pixel (0,0) in the sensor (a crop at x, y: x, y),
// so the mosaic's colours stay where the sensor has them.
//
// Bilinear: a pixel keeps its own colour's value; each other colour is the mean
// of the pixels of that colour among its 8 neighbours (G at R or B: the 4 edge
// neighbours; R at G: the 2 R neighbours; R at B: the 4 corner neighbours).
// At the border, the view is mirrored about its edge pixels (pixel -1 is pixel
// 1, which has the same colour), so a stripe along the border is treated as
// inside. Away from the border, a smooth
// colour plane f comes back within (1/2)(|f_xx| + 2|f_xy| + |f_yy|) (maxima over
// the pixel's 3x3 neighbourhood) of its true value (Taylor: a mean of values at
// +-d is f + d'H d / 2), and exactly for a linear f.
template <typename T>
void DemosaicBilinear(const ImageView<T>& mosaic, ColorFilter filter, int phase_x, int phase_y,
                      std::vector<float>* rgb);
template <typename T>
Image<float> DemosaicBilinear(const ImageView<T>& mosaic, ColorFilter filter, int phase_x = 0, int phase_y = 0) {
  Image<float> out;
  DemosaicBilinear(mosaic, filter, phase_x, phase_y, &out.pixels);
  out.width = mosaic.width;
  out.height = mosaic.height;
  out.channels = 3;
  return out;
}

}  // namespace lt

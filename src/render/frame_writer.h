// Writes a rendered frame into a run folder (render/run_folder.h) and returns
// its manifest line. Files, all written atomically:
//   frames/NNNNNN.png      the sensor's digital numbers. 16-bit PNG: the raw DN
//                          (LSB-aligned, 0..2^bits-1, as machine-vision cameras
//                          deliver Mono12/Mono16); 8-bit PNG: the top 8 bits.
//   radiance/NNNNNN.exr    R, G, B broadband and "laser" radiance, W/(m² sr),
//                          averaged over the exposure (float)
//   gt/NNNNNN.exr          Z (camera depth, m), N.X N.Y N.Z (camera-frame normal),
//                          instance, material, plane (-1: none)
//   gt/NNNNNN_centers.csv  exact stripe centres (frames the lasers light)
#pragma once

#include <nlohmann/json.hpp>

#include "render/frame_renderer.h"
#include "render/run_folder.h"

namespace lt {

nlohmann::json WriteFrame(const RunFolder& run, const RenderedFrame& frame, int index, const SceneFile& scene,
                          uint64_t seed, int spp);

// The 8- or 16-bit PNG image of a raw sensor frame (see above).
Image<uint8_t> RawTo8Bit(const Image<uint16_t>& raw, int bit_depth);

}  // namespace lt

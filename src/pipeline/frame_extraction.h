// The extraction options of one laser frame of a run folder, as `scan` and
// `calibrate laser` both use them (docs/extraction.md, "Colour frames: the
// laser's channels"):
//
//   - a one-channel frame of a colour sensor is a Bayer mosaic: demosaiced;
//   - a colour frame (mosaic or R, G, B) without `channel` or
//     `channel_weights` is extracted on the R, G, B weights matched to the
//     rig's lasers and quantum efficiency (MatchedChannelWeights); a mosaic
//     whose rig cannot give them keeps the mean of R, G and B;
//   - threshold and background kAuto (NaN) follow the frame's bit depth and
//     the sensor's black level (FrameExtractionLevels), in the weighted image's
//     units (ExtractionOptions::WeightedFullScale, WeightedLevel).
#pragma once

#include "core/image_io.h"
#include "pipeline/channel_weights.h"
#include "pipeline/extraction_options.h"
#include "pipeline/run_folder_reader.h"

namespace lt {

struct FrameExtraction {
  ExtractionOptions options;
  // The colour weights came from the rig (options.channel_weights holds them).
  bool matched_weights = false;
  // A mosaic extracted on the mean of R, G and B because the rig cannot give
  // the weights (LaserChannelWeights::missing says why).
  bool mosaic_mean = false;
};

// `given`: the user's options (threshold and background may be kAuto).
// `matched`: MatchedChannelWeights(rig), computed once per run.
FrameExtraction RunFrameExtraction(const ExtractionOptions& given, const RunFrame& frame, const AnyImage& image,
                                   const RunRig& rig, const LaserChannelWeights& matched);

}  // namespace lt

#include "pipeline/frame_extraction.h"

#include <cmath>
#include <variant>

namespace lt {

FrameExtraction RunFrameExtraction(const ExtractionOptions& given, const RunFrame& frame, const AnyImage& image,
                                   const RunRig& rig, const LaserChannelWeights& matched) {
  FrameExtraction r;
  ExtractionOptions& eo = r.options;
  eo = given;
  const int channels = std::visit([](const auto& im) { return im.channels; }, image);
  // The raw frame of a colour sensor is a mosaic: demosaiced before extraction.
  eo.bayer = channels == 1 ? rig.color_filter : ColorFilter::kMono;
  // A three-channel frame the rig gives no weights for needs `channel` or
  // `channel_weights` (the extractor says so); a mosaic keeps the mean.
  const bool colour = eo.bayer != ColorFilter::kMono || channels == 3;
  if (colour && eo.channel < 0 && eo.channel_weights.empty()) {
    if (matched.missing.empty()) {
      eo.channel_weights = matched.weights;
      r.matched_weights = true;
    } else {
      r.mosaic_mean = eo.bayer != ColorFilter::kMono;
    }
  }
  const ExtractionLevels levels = FrameExtractionLevels(given.threshold, given.background, frame, rig.bit_depth,
                                                        rig.black_level_dn, ImageTypeFullScale(image));
  eo.threshold = std::isnan(given.threshold) ? levels.threshold * eo.WeightedFullScale() : levels.threshold;
  eo.background = std::isnan(given.background) ? levels.background * eo.WeightedLevel() : levels.background;
  return r;
}

}  // namespace lt

#include "pipeline/frame_image_reader.h"

#include "core/error.h"

namespace lt {

AnyImage ReadFrameImage(RunFrame* frame, const Camera& camera, const std::string& camera_source,
                        ImageFileWarner* warner, bool warn_transfer_tags) {
  AnyImage image;
  try {
    ImageFileFacts facts;
    image = ReadImage(frame->image, AlphaChannel::kDrop, &facts);
    if (frame->bit_depth <= 0) frame->bit_depth = DeclaredUnscaledBits(facts);
    if (warner) warner->Check(frame->image.string(), facts, !warn_transfer_tags);
  } catch (const InputError& e) {
    throw InputError(e.where(), e.message() + " (frame " + std::to_string(frame->index) + ", " + frame->where + ")");
  }
  CheckFrameImageSize(image, *frame, camera, camera_source);
  return image;
}

}  // namespace lt

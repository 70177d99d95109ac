// How `scan` and `calibrate` read a run's frame images (docs/pipeline.md,
// "Frames and extraction"; docs/extraction.md, "Image files from real
// cameras"): one reader, so that both take the same pixels and bit depth from
// the same file, and say the same about what the file declares.
#pragma once

#include <string>

#include "core/image_io.h"
#include "pipeline/image_file_facts.h"
#include "pipeline/run_folder_reader.h"
#include "sensor/camera.h"

namespace lt {

// The image of `frame`, which must have the size of `camera` (`camera_source`
// names where the camera comes from):
//   - an alpha channel left out (a camera frame's alpha is coverage, not light);
//   - without a bit depth (frame->bit_depth <= 0), the bits its file declares
//     stored unscaled (DeclaredUnscaledBits: a PNG's sBIT) become the frame's
//     (threshold, saturation);
//   - what the file declares and is not applied goes to `warner` (null: nowhere)
//     as ImageFileWarnings: the Orientation tag always, a transfer-curve tag
//     only with `warn_transfer_tags` (a frame extracted as linear without
//     --transfer given; a bright frame's corners need no linear values).
// Throws lt::InputError naming the file and the frame ("(frame N, <where>)").
AnyImage ReadFrameImage(RunFrame* frame, const Camera& camera, const std::string& camera_source,
                        ImageFileWarner* warner, bool warn_transfer_tags);

}  // namespace lt

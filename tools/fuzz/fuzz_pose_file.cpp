// Pose files (pipeline/pose_file.h: ParsePoseFile; CSV, TUM, KITTI, Motive, tf)
// and the scene's pose lists (scene/pose_list.h: ParsePoseList, CSV and TUM).
// The first byte chooses the options: bit 0 units mm, bit 1 order wxyz (else
// xyzw), bit 2 a body "rb1", bit 3 no order, bit 4 pose list TUM, bit 5 an image time offset.
#include "fuzz_common.h"
#include "pipeline/pose_file.h"
#include "scene/pose_list.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const uint8_t flags = data[0];
  const std::string text = lt::fuzz::Text(data + 1, size - 1);
  lt::PoseFileOptions options;
  if (flags & 1) options.units = lt::PoseUnits::kMillimetres;
  if (!(flags & 8)) options.order = (flags & 2) ? lt::QuaternionOrder::kWxyz : lt::QuaternionOrder::kXyzw;
  if (flags & 4) options.body = "rb1";
  if (flags & 32) options.image_time_offset_s = 0.5;
  lt::fuzz::ExpectCleanErrors([&] { lt::ParsePoseFile(text, "poses.csv", options, [](const std::string&) {}); });
  lt::fuzz::ExpectCleanErrors([&] {
    const lt::PoseTrajectory t =
        lt::ParsePoseList(text, (flags & 16) ? lt::PoseFileFormat::kTum : lt::PoseFileFormat::kCsv, "poses.csv");
    (void)t.At(0.5 * (t.StartTime() + t.EndTime()));
  });
  return 0;
}

#include "pipeline/calib_session_run.h"

#include "core/error.h"
#include "core/image_io.h"
#include "pipeline/scan_poses.h"

namespace lt {

namespace fs = std::filesystem;

namespace {

// The tool poses of a pose file: one per frame (or matched by the images'
// times), as scan gives them, or one per bright frame.
std::string GiveToolPoses(const SessionCaptureOptions& o, const std::function<void(const std::string&)>& warn,
                          SessionRun* r) {
  const PoseFile poses = ReadPoseFile(*o.poses, o.pose_file, warn);
  std::vector<size_t> bright;
  for (size_t k = 0; k < r->frames.size(); ++k) {
    if (!r->frames[k].IsLaserFrame()) bright.push_back(k);
  }
  if (!o.pose_file.image_time_offset_s && !bright.empty() && poses.poses.size() != r->frames.size() &&
      poses.poses.size() == bright.size()) {
    std::vector<RunFrame> views;
    for (size_t k : bright) views.push_back(r->frames[k]);
    const std::string source = GivePoses(poses, *o.poses, true, &views, r->source.string() + "'s bright frames");
    for (size_t i = 0; i < bright.size(); ++i) r->frames[bright[i]].world_from_tool = views[i].world_from_tool;
    return source + ", one per bright frame";
  }
  try {
    return GivePoses(poses, *o.poses, true, &r->frames, r->source.string(), o.pose_file.image_time_offset_s);
  } catch (const InputError& e) {
    if (e.where() != o.poses->string() || o.pose_file.image_time_offset_s || bright.empty()) throw;
    throw InputError(e.where(), e.message() + "; or one per bright frame: " + std::to_string(bright.size()));
  }
}

}  // namespace

void SessionCaptureOptions::Check() const {
  if (bit_depth < 0 || bit_depth > 16) throw InputError("--bit-depth", "must be 1..16, got " + std::to_string(bit_depth));
  if (pose_file.image_time_offset_s && !poses) {
    throw InputError("--image-time-offset", "describes a pose file: give it with --poses");
  }
}

SessionRun ReadSessionRun(const fs::path& dir, const SessionCaptureOptions& o,
                          const std::function<void(const std::string&)>& warn) {
  o.Check();
  SessionRun r;
  r.dir = dir;
  r.shutter = o.shutter;
  ScanFrames listed = ReadScanFrames(dir);
  if (listed.frames.empty()) throw InputError(listed.source.string(), "holds no frame (expected one JSON object per line)");
  r.frames = listed.frames;  // listed keeps them for CheckSize
  r.source = listed.source;
  r.from_listing = listed.from_listing;
  ApplyShutterPattern(o.shutter, &r.frames);
  if (HasRunRig(dir)) {
    r.rig = ReadRunRig(dir);
    r.rig_in_run = r.has_camera = true;
  } else if (o.camera) {
    r.rig.camera = *o.camera;
    r.rig.planes_in_cam = o.planes_in_cam;
    r.rig.source = o.camera_source;
    r.has_camera = true;
  } else {
    // No camera: the frames need only one size (the camera step finds the camera).
    const fs::path& first = r.frames.front().image;
    const ImageFileSize size = r.from_listing ? ImageFileSize{listed.width, listed.height} : ReadImageFileSize(first);
    CameraParams p;
    p.width = size.width, p.height = size.height;
    r.rig.camera = Camera(p);
    r.rig.source = first.string() + ", the first frame,";
  }
  listed.CheckSize(r.rig.camera.width(), r.rig.camera.height(), r.rig.source.string());
  r.width = r.rig.camera.width(), r.height = r.rig.camera.height();
  // As scan: --bit-depth is the sensor's (a frame without bit_depth has it), --bayer its mosaic.
  if (o.bit_depth > 0) r.rig.bit_depth = o.bit_depth;
  if (o.color_filter) r.rig.color_filter = *o.color_filter;
  for (RunFrame& f : r.frames) {
    if (f.bit_depth <= 0) f.bit_depth = r.rig.bit_depth;
  }
  if (o.poses) r.pose_source = GiveToolPoses(o, warn, &r);
  return r;
}

}  // namespace lt

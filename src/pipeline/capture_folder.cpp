#include "pipeline/capture_folder.h"

#include <string>

#include "core/error.h"
#include "core/text_fields.h"
#include "core/image_io.h"
#include "pipeline/image_folder.h"

namespace lt {

namespace fs = std::filesystem;

CaptureFolder ReadCaptureFolder(const fs::path& dir) {
  const std::vector<fs::path> top = ImageFilesIn(dir), sub = ImageFilesIn(dir / "frames");
  if (!top.empty() && !sub.empty()) {
    throw InputError(dir.string(), "holds images both directly (" + top.front().filename().string() + ", ...) and in " +
                                       "frames/ (" + sub.front().filename().string() +
                                       ", ...), and no manifest.jsonl: which are the frames? Move the others away");
  }
  if (top.empty() && sub.empty()) {
    throw InputError(dir.string(), std::string("no manifest.jsonl and no image file (") + kImageExtensionsText +
                                       ") in the folder or its frames/ folder");
  }
  CaptureFolder c;
  const std::vector<fs::path>& files = top.empty() ? sub : top;
  c.images_dir = top.empty() ? dir / "frames" : dir;
  std::string first_type;
  const std::string listing = c.images_dir.string() + " (no manifest.jsonl: frames in file name order)";
  for (size_t i = 0; i < files.size(); ++i) {
    const ImageFileSize size = ReadImageFileSize(files[i]);
    if (i == 0) {
      c.width = size.width, c.height = size.height;
      first_type = size.sample_type;
    } else if (size.sample_type != first_type) {
      // Thresholds, black level and saturation follow the sample type: a frame
      // of another type is another camera's or a converted copy.
      throw InputError(files[i].string(), "the image is " + size.sample_type + " but " +
                                              files.front().filename().string() + ", the first frame, is " + first_type +
                                              ": the frames of a capture have one sample type");
    } else if (size.width != c.width || size.height != c.height) {
      throw InputError(files[i].string(), "the image is " + SizeText(size.width, size.height) + " but " +
                                              files.front().filename().string() + ", the first frame, is " +
                                              SizeText(c.width, c.height) + ": the frames of a capture have one size");
    }
    RunFrame f;
    f.index = int(i);
    f.where = listing;
    f.image = files[i];
    c.frames.push_back(std::move(f));
  }
  return c;
}

ScanFrames ReadScanFrames(const fs::path& dir) {
  ScanFrames s;
  std::error_code ec;
  if (fs::is_directory(dir, ec) && !fs::exists(dir / "manifest.jsonl", ec)) {
    CaptureFolder c = ReadCaptureFolder(dir);
    s.frames = std::move(c.frames);
    s.source = c.images_dir;
    s.from_listing = true;
    s.width = c.width, s.height = c.height;
    return s;
  }
  s.frames = ReadRunManifest(dir);
  s.source = dir / "manifest.jsonl";
  return s;
}

void ScanFrames::CheckSize(int camera_width, int camera_height, const std::string& camera_source) const {
  if (!from_listing || frames.empty() || (width == camera_width && height == camera_height)) return;
  throw InputError(frames.front().image.string(), "the image is " + SizeText(width, height) + " but the camera (" +
                                                      camera_source + ") is " + SizeText(camera_width, camera_height));
}

ShutterPattern ParseShutterPattern(const std::string& text, const std::string& option) {
  if (text == "recorded") return ShutterPattern::kRecorded;
  if (text == "alternate") return ShutterPattern::kAlternateLaserFirst;
  if (text == "alternate-bright-first") return ShutterPattern::kAlternateBrightFirst;
  throw InputError(option, "unknown shutter pattern '" + text + "' (expected recorded, alternate or alternate-bright-first)");
}

void ApplyShutterPattern(ShutterPattern pattern, std::vector<RunFrame>* frames) {
  if (pattern == ShutterPattern::kRecorded) return;
  for (size_t k = 0; k < frames->size(); ++k) {
    RunFrame& f = (*frames)[k];
    f.laser_on = (k % 2 == 0) == (pattern == ShutterPattern::kAlternateLaserFirst);
    f.laser_on_known = f.shutter_known = true;
    f.laser_fraction = f.laser_on ? 1.0 : 0.0;  // no bleeding known: a bright frame's colour is not contaminated
  }
}

std::string FloodLitWarning(const std::vector<int>& frames, ShutterPattern pattern, bool from_listing) {
  std::string list;
  for (size_t i = 0; i < frames.size() && i < 5; ++i) list += (i ? ", " : "") + std::to_string(frames[i]);
  if (frames.size() > 5) list += ", ...";
  const std::string head = std::to_string(frames.size()) + " frame" + (frames.size() == 1 ? "" : "s") + " (" + list + ")";
  if (pattern != ShutterPattern::kRecorded) {
    return head + " scanned as laser frames by --shutter " +
           (pattern == ShutterPattern::kAlternateLaserFirst ? "alternate" : "alternate-bright-first") +
           " have most pixels above the stripe threshold: flood-lit (bright) frames give false points; is the "
           "first frame a " + (pattern == ShutterPattern::kAlternateLaserFirst ? "bright one (--shutter alternate-bright-first)?"
                                                                                 : "laser one (--shutter alternate)?");
  }
  return head + (from_listing ? " of a capture without a manifest" : " with no shutter.laser_on in the manifest") +
         " have most pixels above the stripe threshold: flood-lit (bright) frames scanned as laser frames give false "
         "points; " +
         (from_listing ? "--shutter alternate (or alternate-bright-first) says which frames are bright"
                       : "give shutter.laser_on on each manifest line (or --shutter alternate)");
}

}  // namespace lt

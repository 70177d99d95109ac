// The frames of a capture without a manifest (`lasertwin scan DIR` on a folder
// of images from a camera's software, docs/pipeline.md, "A capture without a
// manifest"): the image files directly in DIR, or in DIR/frames, in natural
// order (img2 before img10; names that are numbers, such as times
// "1305031102.2", by value), any extension the image reader takes in any case
// (pipeline/image_folder.h); hidden files (".name", macOS's "._name" copies) and
// sub-folders are left out. Every image must have the size of the first.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/run_folder_reader.h"

namespace lt {

struct CaptureFolder {
  std::filesystem::path images_dir;  // DIR or DIR/frames
  std::vector<RunFrame> frames;      // index 0, 1, ... in natural order; laser frames unless told otherwise
  int width = 0, height = 0;         // of every image
};

// Throws lt::InputError naming the folder when it holds no image (neither
// directly nor in frames/) or holds images in both places, and naming the file
// for an unreadable image or one whose size is not the first image's.
CaptureFolder ReadCaptureFolder(const std::filesystem::path& dir);

// The frames a scan reads: DIR/manifest.jsonl's (ReadRunManifest), or, when
// DIR is a folder without one, the folder listing's (ReadCaptureFolder).
struct ScanFrames {
  std::vector<RunFrame> frames;
  std::filesystem::path source;  // DIR/manifest.jsonl, or the folder of the images
  bool from_listing = false;
  int width = 0, height = 0;     // from_listing: the images' size
  // Throws lt::InputError naming the first image when the listed images' size
  // is not the camera's (before any frame is scanned).
  void CheckSize(int camera_width, int camera_height, const std::string& camera_source) const;
};
ScanFrames ReadScanFrames(const std::filesystem::path& dir);

// How a scan tells laser (dim) frames from bright ones.
enum class ShutterPattern {
  kRecorded,              // the manifest's shutter keys; without them (or a manifest) every frame is a laser frame
  kAlternateLaserFirst,   // frames alternate, the first (in index order) a laser frame: laser, bright, laser, ...
  kAlternateBrightFirst,  // bright, laser, bright, ...
};
// "recorded" | "alternate" (laser first) | "alternate-bright-first"; throws lt::InputError naming `option`.
ShutterPattern ParseShutterPattern(const std::string& text, const std::string& option);
// Sets the frames' commanded laser state (shutter.laser_on) by their position
// in `frames` for the alternating patterns, replacing a manifest's; nothing for kRecorded.
void ApplyShutterPattern(ShutterPattern pattern, std::vector<RunFrame>* frames);
// The warning about frames scanned as laser frames though most of their pixels
// are above the stripe threshold (flood-lit), with what would tell them apart.
std::string FloodLitWarning(const std::vector<int>& frames, ShutterPattern pattern, bool from_listing);

}  // namespace lt

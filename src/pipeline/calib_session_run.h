// How a calibration session's frames are read (`lasertwin calibrate`,
// docs/calibration.md, "A capture without a manifest"): the run's manifest, or,
// for a real capture without one (a folder of images, in it or in its frames/,
// in name order), the folder's listing, as `scan` reads them
// (pipeline/capture_folder.h): the shutter pattern says which frames are
// bright, a pose file (pipeline/scan_poses.h) gives the robot tool's poses, and
// without rig.json or scene.json the camera is a calibration file's.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/capture_folder.h"
#include "pipeline/pose_file.h"
#include "pipeline/run_folder_reader.h"
#include "sensor/camera.h"
#include "sensor/plane.h"

namespace lt {

// How a session's frames are read: the options `scan` reads a capture with.
struct SessionCaptureOptions {
  // Which frames are bright (the board) and which dim (the laser); a capture
  // without a manifest needs an alternating pattern (every frame would be a
  // laser frame).
  ShutterPattern shutter = ShutterPattern::kRecorded;
  // The robot tool's poses (world_from_tool), replacing the manifest's: one per
  // frame in frame order, or poses with times matched to images named by their
  // time (GivePoses), or one per bright frame (a robot program logging the
  // pose it stopped at for each view).
  std::optional<std::filesystem::path> poses;
  PoseFileOptions pose_file;
  int bit_depth = 0;  // the sensor's ADC bits (1..16); 0: the manifest's, rig.json's
  // The raw frames' colour filter mosaic (`--bayer`), as scan's: replaces
  // rig.json's color_filter (a folder without a rig is mono without it).
  std::optional<ColorFilter> color_filter;
  // The camera of a folder without rig.json or scene.json (a calibration
  // file's); its laser planes say how many sheets there are.
  std::optional<Camera> camera;
  std::vector<Plane> planes_in_cam;
  std::string camera_source;  // the file the camera came from, for messages

  void Check() const;  // throws lt::InputError naming the option
};

// A session's frames and scanner, read once.
struct SessionRun {
  std::filesystem::path dir;
  std::vector<RunFrame> frames;   // in index order, shutter pattern applied, tool poses given
  std::filesystem::path source;   // DIR/manifest.jsonl, or the folder of the images
  bool from_listing = false;      // no manifest: the folder's images in name order
  RunRig rig;                     // rig.json's or scene.json's; else the options' camera (rig.source: its file)
  bool rig_in_run = false;        // the rig is the run's own (its ground truth may be compared with)
  bool has_camera = false;        // rig.camera holds a camera (always with rig_in_run)
  int width = 0, height = 0;      // the frames' size
  std::string pose_source;        // what gave the tool poses: "" for the manifest's
  ShutterPattern shutter = ShutterPattern::kRecorded;
};

// Throws lt::InputError naming the file and place: an unreadable manifest or
// folder, a pose file that does not match the frames, a camera of another size
// than the images.
SessionRun ReadSessionRun(const std::filesystem::path& dir, const SessionCaptureOptions& options = {},
                          const std::function<void(const std::string&)>& warn = {});

}  // namespace lt

// Calibration sessions as scenes (`lasertwin calib-session`, docs/calibration.md):
// a planar checkerboard target and the scanner (the sensor section of a rig
// scene) seen from a set of camera poses around it, each pose held across a
// bright frame (LED on, lasers off: the corners) and a dim frame (lasers on,
// LED off: the stripe on the target).
//
// Files written into the session folder:
//   checkerboard.gltf/.bin  the board: black and white squares (two materials)
//                           and a white margin, a flat plane in the board frame
//   checkerboard.json       the board's layout: rows, cols (inner corners),
//                           square_mm, margin_squares
//   poses.csv               the pose list (scene/pose_list.h, csv): each view's
//                           pose twice, at the start of its bright frame and the
//                           end of its dim frame, so it holds across the pair;
//                           world_from_cam, or world_from_tool with `arm`
//   scene.json              the board at world_from_board (object "checkerboard"),
//                           the rig's sensor with the session's shutter cycle,
//                           a "pose_list" motion (with tool_from_cam when `arm`)
//
// Board frame (pipeline/calib_checkerboard.h, OpenCV's): origin at the first
// inner corner, x along a row of corners, y down a column, z into the board;
// the printed side faces −z. The board lies printed side up (world +z) centred
// on the world origin.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/pose.h"
#include "sensor/image_sensor.h"

namespace lt {

struct CalibSessionOptions {
  int rows = 6;               // inner corners down a column
  int cols = 9;               // inner corners along a row (rows + cols even: a symmetric board, docs/calibration.md)
  double square_m = 3e-3;
  int margin_squares = 1;     // white border around the squares
  int views = 12;
  uint64_t seed = 1;
  // The rig: a scene file whose "sensor" section is used (its camera,
  // lasers, LED, image sensor; its shutter's exposures when alternating).
  std::filesystem::path rig_scene;
  int binning = 2;            // camera pixels binned n x n (resolution / n, pitch x n,
                              // the image sensor as scene/sensor_binning.h bins it)
  double min_tilt_deg = 15, max_tilt_deg = 45;  // board normal against the optical axis
  double min_distance_m = 0.072, max_distance_m = 0.09;  // board centre along the optical axis
  int spp = 4;
  // With arm: the pose list holds world_from_tool and the scene's motion places
  // the camera by this hand-eye pose.
  bool arm = false;
  Pose tool_from_cam = DefaultToolFromCam();

  static Pose DefaultToolFromCam();
  // Throws lt::InputError ("option <name>: ...").
  void Check() const;
};

struct CalibSessionView {
  Pose cam_from_board;
  Pose world_from_cam;
  double tilt_deg = 0;
  double distance_m = 0;
};

struct CalibSession {
  Pose world_from_board;
  std::vector<CalibSessionView> views;
  int frames = 0;
};

// Writes the session into `out_dir` (created; existing session files are
// replaced). Throws lt::InputError for a bad rig scene (naming the file and
// JSON pointer), a rig without an LED or without lasers, a shutter that cannot
// hold a pose across a bright/dim pair, or a board that does not fit in the
// image at the requested tilts and distances.
CalibSession WriteCalibSession(const CalibSessionOptions& options, const std::filesystem::path& out_dir);

}  // namespace lt

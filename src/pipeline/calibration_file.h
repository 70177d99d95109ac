// Calibration files: OpenCV FileStorage YAML or XML (pipeline/opencv_yaml.h),
// so a camera calibrated with OpenCV loads directly and ours load in OpenCV.
// The reader takes either form whatever the name; the writer picks the form by
// the extension, as cv::FileStorage does (.xml XML, .yaml/.yml YAML).
// docs/pipeline.md ("Calibration file") documents the keys:
//
//   %YAML:1.0
//   ---
//   image_width: 1280                     camera part (all or none of these four)
//   image_height: 1024
//   camera_matrix: !!opencv-matrix        3x3 [fx 0 cx; 0 fy cy; 0 0 1], pixels
//   distortion_model: brown_conrady       or fisheye (default brown_conrady)
//   fisheye_model: 0                      read only: OpenCV's calibration sample's
//                                         flag (1 fisheye, 0 brown_conrady)
//   distortion_coefficients: !!opencv-matrix
//                                         brown_conrady: k1 k2 p1 p2 [k3 [k4 k5 k6 ...]]
//                                         (4, 5, 8, 12 or 14 values, those after k3 0);
//                                         fisheye: k1 k2 k3 k4; 1xN or Nx1
//   laser_planes: !!opencv-matrix         N x 4, row k = (nx, ny, nz, d) of plane k:
//                                         camera frame, n·p + d = 0, metres
//   tool_from_cam: !!opencv-matrix        4x4 rigid transform (hand-eye), metres
//   depth_min_mm: 60                      the scanner's working range, camera z
//   depth_max_mm: 120                     (both or neither; pipeline/plane_id_sheets.h)
//
// Pixel coordinates follow OpenCV (centre of pixel (0,0) at (0,0)). Plane k is
// global plane number k: the sheets of laser 0 first, then laser 1, ... Keys
// other than these are ignored and listed in `ignored_keys` (so the caller can
// warn about a misspelt key), so files OpenCV's calibration tools write, with
// their extra entries, load.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"
#include "pipeline/opencv_yaml.h"
#include "pipeline/plane_id_sheets.h"
#include "sensor/camera.h"
#include "sensor/plane.h"

namespace lt {

// The camera part of a calibration file: intrinsics and distortion.
struct CalibratedCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  DistortionModel distortion = DistortionModel::kNone;
  BrownConradyCoeffs brown_conrady;
  KannalaBrandtCoeffs fisheye;

  // From a camera (for writing its calibration).
  static CalibratedCamera From(const Camera& camera);
  // `base` with these intrinsics and this distortion (pixel pitch, f-number and
  // focus stay from base: triangulation does not need them).
  CameraParams ApplyTo(CameraParams base) const;
};

struct CalibrationFile {
  std::optional<CalibratedCamera> camera;
  std::vector<Plane> laser_planes;  // camera frame, unit normals
  std::optional<Pose> tool_from_cam;
  std::optional<DepthRange> depth_range;  // depth_min_mm, depth_max_mm
  std::vector<std::string> ignored_keys;  // read only
  // Read only: what the reader could not honour fully ("file: line: ..."),
  // for the caller to print (a ROS rectification that is not the identity).
  std::vector<std::string> warnings;

  // Builds the camera (base supplies the non-geometric parameters). Throws
  // lt::InputError naming `file` when the distortion folds inside the image.
  Camera MakeCamera(const CameraParams& base, const std::string& file) const;
};

// Which camera of a file of several to read (--calib-camera).
struct CalibrationFileOptions {
  // A Kalibr camchain's key (cam1), a VINS-Fusion config's camera (cam1: its
  // cam1_calib file), a COLMAP cameras.txt's CAMERA_ID; for a file of one
  // camera, its name (Kalibr's key, camera_name), which must match. Unset: a
  // file of several cameras is an error naming them.
  std::optional<std::string> camera;
};

// Reads a calibration file; errors are lt::InputError naming "file:line".
// Plane normals are normalised (n and d divided by |n|) unless already unit to 1e-12.
// Besides OpenCV's FileStorage YAML and XML, the camera files of ROS
// (camera_info), Kalibr (camchain) and camodocal are read for their camera
// (pipeline/camera_file_formats.h). A file from which nothing is read (no
// camera, laser_planes, tool_from_cam or working range) is an error, as is
// options.camera for an OpenCV file (one camera, unnamed).
CalibrationFile ReadCalibrationFile(const std::filesystem::path& path, const CalibrationFileOptions& options = {});
// What a reader of `file` warns about after reading it, one line each (a
// command prints each as "lasertwin: warning: LINE"): its ignored keys on one
// line however many, "FILE: key K is FATE" or "FILE: N keys (the first 8 and M
// more) are FATE", then the readers' warnings (CalibrationFile::warnings).
// `fate` is what the caller does with the keys ("ignored"; calibrate: "not kept
// in the output").
std::vector<std::string> CalibrationFileWarnings(const CalibrationFile& calibration, const std::string& file,
                                                 const std::string& fate);
// The form a calibration file of this name is written in: .xml is XML, .yaml
// and .yml are YAML (any case). Throws lt::InputError naming the path for any
// other extension (or none), so no file holds one form under another's name.
StorageFormat CalibrationFileFormat(const std::filesystem::path& path);
// The file's text (what WriteCalibrationFile writes). Throws std::invalid_argument
// on non-finite values.
std::string FormatCalibrationFile(const CalibrationFile& calibration, StorageFormat format = StorageFormat::kYaml);
// Written atomically, in the form of CalibrationFileFormat(path) (which throws
// before anything is written).
void WriteCalibrationFile(const std::filesystem::path& path, const CalibrationFile& calibration);

}  // namespace lt

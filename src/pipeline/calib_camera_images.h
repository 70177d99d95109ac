// Camera calibration from a folder of photographs of the checkerboard, as a
// camera or a phone delivers them (no run manifest): every image file of the
// folder, in natural name order (pipeline/image_folder.h), is one view (docs/calibration.md, "Calibrating from
// a folder of photographs").
#pragma once

#include <filesystem>
#include <vector>

#include "pipeline/calib_camera.h"
#include "pipeline/calib_checkerboard.h"
#include "pipeline/calib_corners.h"
#include "pipeline/image_folder.h"

namespace lt {

struct PhotoView {
  std::filesystem::path image;
  CornerDetection detection;
};

struct PhotoCameraResult {
  int width = 0, height = 0;  // of every image
  std::vector<PhotoView> views;
  std::vector<int> used;  // indices into views of the calibrated views, in the calibration's order
  CameraCalibrationResult calibration;
};

// Detects the board on each image and calibrates the camera from the views
// where it was found whole. Throws lt::InputError naming the file for an
// unreadable image, and for an image whose size differs from the first
// one's (both sizes in the message): the intrinsics belong to one image size.
PhotoCameraResult CalibrateCameraFromImages(const std::vector<std::filesystem::path>& images,
                                            const CheckerboardSpec& board,
                                            const CameraCalibrationOptions& options = {},
                                            const CornerDetectionOptions& corners = {});

}  // namespace lt

// Camera calibration from a folder of photographs of the checkerboard, as a
// camera or a phone delivers them (no run manifest): every image file of the
// folder, in natural name order (pipeline/image_folder.h), is one view (docs/calibration.md, "Calibrating from
// a folder of photographs").
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "pipeline/calib_camera.h"
#include "pipeline/calib_checkerboard.h"
#include "pipeline/calib_corners.h"
#include "pipeline/image_folder.h"
#include "sensor/image_sensor.h"

namespace lt {

// The image the corner detector reads of a camera image. A one-channel image of
// a colour sensor (`filter` not kMono) is its raw Bayer mosaic, whose 2x2
// filter pattern is a fine checker on every square (a red board reads dark
// behind the green filters): it is white-balanced (each colour's 1st and 99th
// percentiles mapped onto G's), demosaiced bilinearly as scan's extraction
// does (pipeline/demosaic.h) and taken as the mean of R, G and B: a float
// image in G's units. Any other image comes back as it is (the detector
// averages the channels of a colour one).
AnyImage CornerDetectionImage(AnyImage image, ColorFilter filter);

struct PhotoView {
  std::filesystem::path image;
  CornerDetection detection;
};

struct PhotoCameraResult {
  int width = 0, height = 0;  // of every image
  std::vector<PhotoView> views;
  std::vector<int> used;  // indices into views of the calibrated views, in the calibration's order
  int one_channel = 0;    // images of one channel (grey, or the mosaic of `color_filter`)
  CameraCalibrationResult calibration;
};

// Detects the board on each image and calibrates the camera from the views
// where it was found whole. Throws lt::InputError naming the file for an
// unreadable image, and for an image whose size differs from the first
// one's (both sizes in the message): the intrinsics belong to one image size.
// `color_filter` (`--bayer`): the one-channel images are that colour sensor's
// raw mosaics (CornerDetectionImage); kMono: they are grey. An image's
// Orientation tag (a phone's photo) is not applied: `warn` is told so, once,
// with the count of the other images it holds for at the end (ImageFileWarner).
PhotoCameraResult CalibrateCameraFromImages(const std::vector<std::filesystem::path>& images,
                                            const CheckerboardSpec& board,
                                            const CameraCalibrationOptions& options = {},
                                            const CornerDetectionOptions& corners = {},
                                            ColorFilter color_filter = ColorFilter::kMono,
                                            const std::function<void(const std::string&)>& warn = {});

}  // namespace lt

#include "pipeline/calib_camera_images.h"

#include <string>
#include <variant>

#include "core/error.h"
#include "core/text_fields.h"
#include "core/image_io.h"

namespace lt {

namespace fs = std::filesystem;

PhotoCameraResult CalibrateCameraFromImages(const std::vector<fs::path>& images, const CheckerboardSpec& board,
                                            const CameraCalibrationOptions& options,
                                            const CornerDetectionOptions& corners) {
  options.Check();
  corners.Check();
  board.Check();
  PhotoCameraResult r;
  std::vector<CalibrationView> views;
  for (const fs::path& path : images) {
    const AnyImage image = ReadImage(path);
    const auto [w, h] = std::visit([](const auto& i) { return std::pair{i.width, i.height}; }, image);
    if (r.views.empty()) {
      r.width = w, r.height = h;
    } else if (w != r.width || h != r.height) {
      throw InputError(path.string(), "the image is " + SizeText(w, h) + " but " + r.views.front().image.string() +
                                          " is " + SizeText(r.width, r.height) +
                                          ": calibrate images of one size (one camera mode) together");
    }
    PhotoView v{path, DetectCheckerboard(image, board, corners)};
    if (v.detection.ok) {
      views.push_back(ViewOfDetection(board, v.detection));
      r.used.push_back(int(r.views.size()));
    }
    r.views.push_back(std::move(v));
  }
  r.calibration = CalibrateCamera(views, r.width, r.height, options);
  return r;
}

}  // namespace lt

#include "pipeline/calib_camera_images.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <variant>

#include "core/error.h"
#include "core/image_io.h"

namespace lt {

namespace fs = std::filesystem;

namespace {

bool IsImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".pgm", ".ppm", ".pnm", ".exr"}) {
    if (ext == e) return true;
  }
  return false;
}

std::string Size(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

std::vector<fs::path> ListImageFiles(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) throw InputError(folder.string(), "no such folder");
  if (!fs::is_directory(folder, ec)) throw InputError(folder.string(), "not a folder");
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
    if (e.is_regular_file(ec) && IsImageFile(e.path())) files.push_back(e.path());
  }
  if (ec) throw InputError(folder.string(), "cannot list the folder: " + ec.message());
  if (files.empty()) {
    throw InputError(folder.string(), "no image files in the folder (.png, .jpg, .jpeg, .tif, .tiff, .bmp, .pgm, "
                                      ".ppm, .pnm, .exr), and no manifest.jsonl of a run");
  }
  std::sort(files.begin(), files.end());
  return files;
}

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
      throw InputError(path.string(), "the image is " + Size(w, h) + " but " + r.views.front().image.string() +
                                          " is " + Size(r.width, r.height) +
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

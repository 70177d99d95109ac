#include "pipeline/calib_camera_images.h"

#include <algorithm>
#include <string>
#include <tuple>
#include <variant>

#include "core/error.h"
#include "core/text_fields.h"
#include "core/image_io.h"
#include "pipeline/demosaic.h"
#include "pipeline/image_file_facts.h"

namespace lt {

namespace fs = std::filesystem;

namespace {

// The q-quantile of `values` (reordered).
float Quantile(std::vector<float>* values, double q) {
  const auto k = values->begin() + std::ptrdiff_t(q * double(values->size() - 1));
  std::nth_element(values->begin(), k, values->end());
  return *k;
}

}  // namespace

AnyImage CornerDetectionImage(AnyImage image, ColorFilter filter) {
  if (filter == ColorFilter::kMono) return image;
  return std::visit(
      [&](auto& raw) -> AnyImage {
        if (raw.channels != 1 || raw.pixels.empty()) return std::move(raw);
        const int W = raw.width, H = raw.height;
        // White balance: each colour's pixels sample the same scene, so the
        // 1st and 99th percentiles of R and B are mapped onto G's (gain and
        // black level together). A board of one hue (the sensor's colour
        // response, the light's colour) then reads as a grey image at every
        // pixel; demosaicing alone leaves a zipper along the squares' edges
        // (its taps differ between the mosaic's four phases).
        std::vector<float> of[3];
        for (int y = 0; y < H; ++y) {
          for (int x = 0; x < W; ++x) of[FilterChannel(filter, x, y)].push_back(float(raw.At(x, y)));
        }
        double lo[3] = {0, 0, 0}, gain[3] = {1, 1, 1};
        if (!of[0].empty() && !of[1].empty() && !of[2].empty()) {  // else a view of 1 px across: as it is
          for (int c = 0; c < 3; ++c) lo[c] = Quantile(&of[c], 0.01);
          const double range_g = Quantile(&of[1], 0.99) - lo[1];
          for (int c : {0, 2}) {
            const double range = Quantile(&of[c], 0.99) - lo[c];
            if (range > 0 && range_g > 0) gain[c] = range_g / range;  // else flat: only moved to G's level
          }
        }
        Image<float> balanced(W, H, 1);
        for (int y = 0; y < H; ++y) {
          for (int x = 0; x < W; ++x) {
            const int c = FilterChannel(filter, x, y);
            balanced.At(x, y) = float(lo[1] + (double(raw.At(x, y)) - lo[c]) * gain[c]);
          }
        }
        // Then demosaiced (what is left of the mosaic where the scene's
        // colours differ from the board's is averaged out) and grey.
        const Image<float> rgb = DemosaicBilinear(balanced.View(), filter);
        Image<float> grey(W, H, 1);
        for (size_t i = 0; i < grey.pixels.size(); ++i) {
          grey.pixels[i] = (rgb.pixels[3 * i] + rgb.pixels[3 * i + 1] + rgb.pixels[3 * i + 2]) / 3.0f;
        }
        return grey;
      },
      image);
}

PhotoCameraResult CalibrateCameraFromImages(const std::vector<fs::path>& images, const CheckerboardSpec& board,
                                            const CameraCalibrationOptions& options,
                                            const CornerDetectionOptions& corners, ColorFilter color_filter,
                                            const std::function<void(const std::string&)>& warn) {
  options.Check();
  corners.Check();
  board.Check();
  PhotoCameraResult r;
  std::vector<CalibrationView> views;
  ImageFileWarner warner(warn, "image");
  for (const fs::path& path : images) {
    ImageFileFacts facts;
    AnyImage image = ReadImage(path, AlphaChannel::kDrop, &facts);  // alpha is coverage, not light (as scan's frames)
    // The corners need no linear values: the Orientation tag alone is said.
    warner.Check(path.string(), facts, /*transfer_given=*/true);
    const auto [w, h, c] = std::visit([](const auto& i) { return std::tuple{i.width, i.height, i.channels}; }, image);
    if (r.views.empty()) {
      r.width = w, r.height = h;
    } else if (w != r.width || h != r.height) {
      throw InputError(path.string(), "the image is " + SizeText(w, h) + " but " + r.views.front().image.string() +
                                          " is " + SizeText(r.width, r.height) +
                                          ": calibrate images of one size (one camera mode) together");
    }
    r.one_channel += c == 1;
    PhotoView v{path, DetectCheckerboard(CornerDetectionImage(std::move(image), color_filter), board, corners)};
    if (v.detection.ok) {
      views.push_back(ViewOfDetection(board, v.detection));
      r.used.push_back(int(r.views.size()));
    }
    r.views.push_back(std::move(v));
  }
  warner.SayRepeats();
  r.calibration = CalibrateCamera(views, r.width, r.height, options);
  return r;
}

}  // namespace lt

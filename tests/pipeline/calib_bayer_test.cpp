// Calibration on a colour (Bayer) sensor: the bright frames and photographs of
// the board are one-channel raw mosaics, which the corner detector must read
// demosaiced (pipeline/calib_camera_images.h, CornerDetectionImage), not raw:
// the mosaic's 2x2 filter gains are a fine checker on every square.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <utility>
#include <variant>
#include <unistd.h>

#include "core/image_io.h"
#include "pipeline/calib_camera_images.h"
#include "pipeline/calib_session.h"
#include "calib_test_util.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

Camera TestCamera() { return Camera(Camera640Params({-0.18, 0.09, 0, 0, 0})); }

std::vector<Pose> Views() {
  return {BoardPose(0, 0, 0.20, 30 * kDeg, 0, 0), BoardPose(0.03, -0.02, 0.21, 35 * kDeg, 90 * kDeg, 15 * kDeg),
          BoardPose(-0.03, 0.02, 0.22, 30 * kDeg, 45 * kDeg, -20 * kDeg),
          BoardPose(0.03, 0.025, 0.19, 25 * kDeg, 135 * kDeg, 180 * kDeg)};
}

// The RGGB mosaic (10-bit DN) of a coloured board: each pixel the board's grey
// level (RenderCheckerboard, 1% noise) times its filter's gain.
Image<uint16_t> MosaicOfColouredBoard(const Pose& cam_from_board, uint64_t seed, double r, double g, double b) {
  SyntheticBoardOptions o;
  o.noise_sigma = 0.01 * (o.white - o.black);
  o.seed = seed;
  const Image<float> grey = RenderCheckerboard(TestCamera(), cam_from_board, Board(), o);
  Image<uint16_t> img(grey.width, grey.height, 1);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const double gain = (y % 2 == 0) ? (x % 2 == 0 ? r : g) : (x % 2 == 0 ? g : b);  // R G / G B
      img.At(x, y) = uint16_t(std::clamp(std::lround(1000.0 * gain * grey.At(x, y)), 0L, 1023L));
    }
  }
  return img;
}

// RMS (per axis) of the detected corners against the true board's projection.
double CornerRms(const CornerDetection& d, const Pose& cam_from_board) {
  const Camera cam = TestCamera();
  const auto points = Board().CornerPoints();
  double sum = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d truth = *cam.Project(cam_from_board * points[i]);
    sum += (d.corners[i] - truth).squaredNorm();
  }
  return std::sqrt(sum / (2.0 * double(points.size())));
}

// A colour sensor's capture of the board (no manifest; bright frames of a
// board of hue (r, g, b) as RGGB mosaics, dark laser frames), and its bright
// frames alone as photographs in DIR/photos.
std::filesystem::path WriteCapture(double r, double g, double b) {
  const auto dir = std::filesystem::temp_directory_path() / ("lt_calib_bayer_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "frames");
  std::filesystem::create_directories(dir / "photos");
  const std::vector<Pose> views = Views();
  for (size_t v = 0; v < views.size(); ++v) {
    const Image<uint16_t> mosaic = MosaicOfColouredBoard(views[v], 40 + v, r, g, b);
    WriteImage(dir / "frames" / (std::to_string(2 * v) + ".png"), mosaic);
    WriteImage(dir / "frames" / (std::to_string(2 * v + 1) + ".png"), Image<uint16_t>(640, 480, 1));
    WriteImage(dir / "photos" / (std::to_string(v) + ".png"), mosaic);
  }
  return dir;
}

// The corners of a colour sensor's board are as accurate as a mono sensor's
// (0.011-0.017 px RMS per view on these boards read as grey). Read raw, the
// mosaic's filter gains made a fine checker on every square: a board of hue
// (1, 0.8, 0.6) came out at 0.022-0.041 px, one of (1, 0.5, 0.3) was not
// found at all ("no contrast": the mosaic read as noise); demosaiced without
// the white balance, 0.025-0.052 and 0.045-0.12 px (the zipper along the
// edges). The first hue through a session's bright frames, the second
// through a folder of photographs.
TEST(CalibBayer, ColourSensorsBoardIsReadDemosaiced) {
  const std::vector<Pose> views = Views();
  for (const auto& hue : {std::array<double, 3>{1.0, 0.8, 0.6}, std::array<double, 3>{1.0, 0.5, 0.3}}) {
    const auto dir = WriteCapture(hue[0], hue[1], hue[2]);
    const bool session = hue[1] == 0.8;
    SCOPED_TRACE(session ? "session, hue 1, 0.8, 0.6" : "photographs, hue 1, 0.5, 0.3");
    std::vector<CornerDetection> found;
    if (session) {
      // A capture read with --bayer rggb (rig.json's color_filter alike).
      SessionCaptureOptions o;
      o.shutter = ShutterPattern::kAlternateBrightFirst;
      o.bit_depth = 10;
      o.camera = TestCamera();
      o.camera_source = "cam.yaml";
      o.color_filter = ColorFilter::kRGGB;
      for (const SessionView& v : ReadSessionViews(ReadSessionRun(dir, o), Board())) found.push_back(v.detection);
    } else {
      // A folder of photographs with --bayer rggb.
      const PhotoCameraResult photos =
          CalibrateCameraFromImages(ListImageFiles(dir / "photos"), Board(), {}, {}, ColorFilter::kRGGB);
      EXPECT_EQ(photos.one_channel, int(views.size()));
      EXPECT_TRUE(photos.calibration.ok) << photos.calibration.reason;
      for (const PhotoView& v : photos.views) found.push_back(v.detection);
    }
    ASSERT_EQ(found.size(), views.size());
    for (size_t v = 0; v < views.size(); ++v) {
      ASSERT_TRUE(found[v].ok) << "view " << v << ": " << found[v].reason;
      EXPECT_LT(CornerRms(found[v], views[v]), 0.02) << "view " << v;
    }
    std::filesystem::remove_all(dir);
  }
}

// The detector's image of a mosaic is the mosaic's size, for any size (a
// 1-pixel-wide image lacks a colour: no white balance, no out-of-range read);
// a grey image, or colour one, or any image read as mono, comes back as it is.
TEST(CalibBayer, CornerImageOfAnySize) {
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{1, 5}, std::pair{5, 1}, std::pair{2, 2}, std::pair{7, 3}}) {
    Image<uint8_t> m(w, h, 1);
    for (size_t i = 0; i < m.pixels.size(); ++i) m.pixels[i] = uint8_t(10 + 7 * i);
    const AnyImage g = CornerDetectionImage(m, ColorFilter::kGBRG);
    ASSERT_TRUE(std::holds_alternative<Image<float>>(g));
    const Image<float>& f = std::get<Image<float>>(g);
    EXPECT_EQ(f.width, w);
    EXPECT_EQ(f.height, h);
    EXPECT_EQ(f.channels, 1);
  }
  const Image<uint16_t> grey(4, 4, 1, 100), rgb(4, 4, 3, 100);
  EXPECT_TRUE(std::holds_alternative<Image<uint16_t>>(CornerDetectionImage(grey, ColorFilter::kMono)));
  EXPECT_TRUE(std::holds_alternative<Image<uint16_t>>(CornerDetectionImage(rgb, ColorFilter::kRGGB)));
  // A flat mosaic of one hue is one grey level: G's.
  Image<uint16_t> flat(6, 6, 1);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x) flat.At(x, y) = uint16_t(FilterChannel(ColorFilter::kRGGB, x, y) == 1 ? 400 : 200);
  const AnyImage balanced = CornerDetectionImage(flat, ColorFilter::kRGGB);
  for (float v : std::get<Image<float>>(balanced).pixels) EXPECT_FLOAT_EQ(v, 400.f);
}

}  // namespace
}  // namespace lt

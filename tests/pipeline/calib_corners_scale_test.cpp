// Checkerboard detection at another scale (docs/calibration.md, "Corner
// detection"): boards the default sigma_px refuses as too blurred or too
// small, found with the default options; occluded and partly visible boards
// still refused at every scale.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/random.h"
#include "pipeline/calib_corners.h"
#include "pipeline/gaussian_filter.h"
#include "sensor/camera.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

Camera SmallCamera(int w, int h, double f) {
  CameraParams p;
  p.width = w;
  p.height = h;
  p.fx = p.fy = f;
  p.cx = (w - 1) / 2.0 + 1.3;
  p.cy = (h - 1) / 2.0 - 0.7;
  return Camera(p);
}

CheckerboardSpec Spec(int rows, int cols) {
  CheckerboardSpec b;
  b.rows = rows;
  b.cols = cols;
  b.square_m = 0.01;
  return b;
}

// The board's centre on the ray of pixel (u, v), squares of about square_px
// (seen frontally), tilted by `tilt` about the in-plane axis at angle `axis`,
// turned by `spin` in its plane.
Pose Place(const Camera& cam, const CheckerboardSpec& b, double u, double v, double square_px, double tilt, double axis,
           double spin) {
  const double z = cam.fx() * b.square_m / square_px;
  const Eigen::Vector3d ray = *cam.Unproject({u, v});
  const Eigen::Vector3d centre(0.5 * (b.cols - 1) * b.square_m, 0.5 * (b.rows - 1) * b.square_m, 0);
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)) *
                Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  p.translation() = ray / ray.z() * z - p.linear() * centre;
  return p;
}

Image<float> GaussianBlur(const Image<float>& in, double sigma) {
  const GaussianKernels k(sigma);
  const int w = in.width, h = in.height;
  Image<float> rows(w, h, 1), out(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double v = 0;
      for (int d = -k.radius; d <= k.radius; ++d) v += k.k0[size_t(d + k.radius)] * in.At(MirrorIndex(x + d, w), y);
      rows.At(x, y) = float(v);
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double v = 0;
      for (int d = -k.radius; d <= k.radius; ++d) v += k.k0[size_t(d + k.radius)] * rows.At(x, MirrorIndex(y + d, h));
      out.At(x, y) = float(v);
    }
  return out;
}

// Linear motion blur: the mean along a segment of `length` pixels at `angle`.
Image<float> MotionBlur(const Image<float>& in, double length, double angle) {
  auto bilinear = [&](double x, double y) {
    x = std::clamp(x, 0.0, in.width - 1.001);
    y = std::clamp(y, 0.0, in.height - 1.001);
    const int x0 = int(x), y0 = int(y);
    const double fx = x - x0, fy = y - y0;
    return (1 - fy) * ((1 - fx) * in.At(x0, y0) + fx * in.At(x0 + 1, y0)) +
           fy * ((1 - fx) * in.At(x0, y0 + 1) + fx * in.At(x0 + 1, y0 + 1));
  };
  Image<float> out(in.width, in.height, 1);
  const int n = int(4 * length);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      double s = 0;
      for (int k = 0; k < n; ++k) {
        const double t = ((k + 0.5) / n - 0.5) * length;
        s += bilinear(x + t * std::cos(angle), y + t * std::sin(angle));
      }
      out.At(x, y) = float(s / n);
    }
  return out;
}

// Black 80, white 140 of 255 (a matte print in dim light), noise in
// fractions of 255, rounded to 8 bits.
Image<uint8_t> ToEightBit(const Image<float>& img, double noise, uint64_t seed) {
  Image<uint8_t> out(img.width, img.height, 1);
  for (size_t k = 0; k < img.pixels.size(); ++k) {
    const double v = 80 + 60 * img.pixels[k] + noise * 255 * Rng::For(seed, 0, k, 0).NextGaussian();
    out.pixels[k] = uint8_t(std::clamp(std::lround(v), 0L, 255L));
  }
  return out;
}

Image<float> Render(const Camera& cam, const Pose& pose, const CheckerboardSpec& b) {
  SyntheticBoardOptions o;
  o.black = 0, o.white = 1, o.background = 0.5;
  o.supersampling = 8;
  return RenderCheckerboard(cam, pose, b, o);
}

// RMS error per axis against the exact corners.
double RmsError(const CornerDetection& d, const Camera& cam, const Pose& pose, const CheckerboardSpec& b) {
  const auto pts = b.CornerPoints();
  double s = 0;
  for (size_t k = 0; k < pts.size(); ++k) s += (d.corners[k] - *cam.Project(pose * pts[k])).squaredNorm();
  return std::sqrt(s / (2.0 * double(pts.size())));
}

struct Outcome {
  CornerDetection fixed;  // at sigma_px = 1.5 only (the behaviour before)
  CornerDetection det;    // default options
};

Outcome Detect(const Image<uint8_t>& img, const CheckerboardSpec& b) {
  CornerDetectionOptions only;
  only.other_scales = false;
  return {DetectCheckerboard(img.View(), b, only), DetectCheckerboard(img.View(), b)};
}

// Motion blur of 12 px across 30 px squares: at sigma_px = 1.5 a grid of a
// few corners; found at sigma_px = 3.
TEST(CalibCornersScale, MotionBlurOf12Pixels) {
  const Camera cam = SmallCamera(320, 240, 400);
  const CheckerboardSpec b = Spec(4, 5);
  const Pose pose = Place(cam, b, cam.cx(), cam.cy(), 30, 20 * kDeg, 30 * kDeg, 10 * kDeg);
  const Outcome r = Detect(ToEightBit(MotionBlur(Render(cam, pose, b), 12, 0.3), 0.01, 1), b);
  EXPECT_FALSE(r.fixed.ok);
  ASSERT_TRUE(r.det.ok) << r.det.reason;
  EXPECT_DOUBLE_EQ(r.det.sigma_px, 3);
  EXPECT_EQ(r.det.other_scales_tried, 1);
  EXPECT_LT(RmsError(r.det, cam, pose, b), 0.1);  // measured 0.048 px
}

// Gaussian blur of 3 px and 2% noise on 150 px squares: at sigma_px = 1.5
// whether a corner's saddle stands out of the noise is a matter of chance
// (2 of 8 noise seeds refused with one corner short, 2 of 2 on a 4 x 5 board);
// found at sigma_px = 3.
TEST(CalibCornersScale, BlurAndNoiseOnLargeSquares) {
  const Camera cam = SmallCamera(640, 480, 1600);
  const CheckerboardSpec b = Spec(2, 3);
  const Pose pose = Place(cam, b, cam.cx(), cam.cy(), 150, 25 * kDeg, 30 * kDeg, 10 * kDeg);
  const Outcome r = Detect(ToEightBit(GaussianBlur(Render(cam, pose, b), 3), 0.02, 2), b);
  EXPECT_FALSE(r.fixed.ok);
  ASSERT_TRUE(r.det.ok) << r.det.reason;
  EXPECT_DOUBLE_EQ(r.det.sigma_px, 3);
  EXPECT_LT(RmsError(r.det, cam, pose, b), 0.25);  // measured 0.14 px
}

// Squares of 8 px at 50 degrees of tilt and 10 px at 60 degrees: too small
// for sigma_px = 1.5 on the far side; found at sigma_px = 1.
TEST(CalibCornersScale, SmallSquaresSeenObliquely) {
  const Camera cam = SmallCamera(320, 240, 400);
  const CheckerboardSpec b = Spec(7, 10);
  for (const auto& [square, tilt] : {std::pair{8.0, 50.0}, std::pair{10.0, 60.0}}) {
    SCOPED_TRACE(testing::Message() << square << " px squares, tilt " << tilt);
    const Pose pose = Place(cam, b, cam.cx(), cam.cy(), square, tilt * kDeg, 30 * kDeg, 10 * kDeg);
    const Outcome r = Detect(ToEightBit(GaussianBlur(Render(cam, pose, b), 0.6), 0.01, 3), b);
    EXPECT_FALSE(r.fixed.ok);
    ASSERT_TRUE(r.det.ok) << r.det.reason;
    EXPECT_DOUBLE_EQ(r.det.sigma_px, 1);
    EXPECT_LT(RmsError(r.det, cam, pose, b), 0.1);  // measured 0.049 and 0.053 px
  }
}

// An occluding disc of 6 px radius beside corner (1, 2), the image blurred by
// 2 px: at sigma_px = 3 and 4.5 the kernel averages the occluder's
// surroundings into a saddle 0.9 px off the hidden corner. The point asymmetry
// about that saddle and the requested scale (no saddle there) refuse it.
TEST(CalibCornersScale, OccludedCornerStaysRefused) {
  const Camera cam = SmallCamera(320, 240, 400);
  const CheckerboardSpec b = Spec(4, 5);
  const Pose pose = Place(cam, b, cam.cx(), cam.cy(), 24, 20 * kDeg, 30 * kDeg, 10 * kDeg);
  Image<float> img = Render(cam, pose, b);
  const Eigen::Vector2d centre = *cam.Project(pose * b.CornerPoints()[size_t(b.cols + 2)]) + Eigen::Vector2d(1.5, 0.9);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double a = std::clamp(6.5 - (Eigen::Vector2d(x, y) - centre).norm(), 0.0, 1.0);
      img.At(x, y) = float((1 - a) * img.At(x, y) + a * 0.3);
    }
  const Outcome r = Detect(ToEightBit(GaussianBlur(img, 2), 0.01, 4), b);
  EXPECT_FALSE(r.fixed.ok);
  EXPECT_FALSE(r.det.ok);
  EXPECT_TRUE(r.det.corners.empty());
  // The reason is that of the requested scale, with the others named.
  EXPECT_NE(r.det.reason.find("for sigma_px = 1.5 (also refused at sigma_px = 3, 4.5, 1, 0.7)"), std::string::npos)
      << r.det.reason;
  EXPECT_EQ(r.det.grid.size(), r.fixed.grid.size());
  EXPECT_DOUBLE_EQ(r.det.sigma_px, 1.5);
}

// A board whose last column of corners is outside the image, sharp and
// blurred: refused at every scale.
TEST(CalibCornersScale, PartlyVisibleBoardStaysRefused) {
  const Camera cam = SmallCamera(320, 240, 400);
  const CheckerboardSpec b = Spec(4, 5);
  const Pose pose = Place(cam, b, 275, cam.cy(), 24, 10 * kDeg, 30 * kDeg, 5 * kDeg);
  for (double blur : {0.6, 3.0}) {
    const Outcome r = Detect(ToEightBit(GaussianBlur(Render(cam, pose, b), blur), 0.01, 5), b);
    EXPECT_FALSE(r.det.ok) << "blur " << blur;
    EXPECT_EQ(r.det.other_scales_tried, 4);
  }
}

// A board of another size than asked for: no scale can cure that, none is tried.
TEST(CalibCornersScale, NoOtherScaleForABoardOfAnotherSize) {
  const Camera cam = SmallCamera(320, 240, 400);
  const CheckerboardSpec b = Spec(4, 5);
  const Pose pose = Place(cam, b, cam.cx(), cam.cy(), 24, 20 * kDeg, 30 * kDeg, 10 * kDeg);
  const Image<uint8_t> img = ToEightBit(GaussianBlur(Render(cam, pose, b), 0.6), 0.01, 6);
  for (const auto& [rows, cols] : {std::pair{3, 4}, std::pair{5, 6}}) {  // smaller and larger than the board
    const CornerDetection d = DetectCheckerboard(img.View(), Spec(rows, cols));
    EXPECT_FALSE(d.ok);
    EXPECT_EQ(d.grid.size(), 20u);
    EXPECT_EQ(d.other_scales_tried, 0) << rows << " x " << cols;
  }
  // The board itself: found at the requested scale.
  const CornerDetection d = DetectCheckerboard(img.View(), b);
  ASSERT_TRUE(d.ok) << d.reason;
  EXPECT_EQ(d.other_scales_tried, 0);
  EXPECT_DOUBLE_EQ(d.sigma_px, 1.5);
}

}  // namespace
}  // namespace lt

// Checkerboard detection on synthetic images: boards projected through a
// pinhole + Brown–Conrady camera, each pixel the board's mean over its area.
#include <gtest/gtest.h>

#include "calib_test_util.h"

#include <cmath>
#include <functional>

#include "core/error.h"
#include "core/random.h"
#include "pipeline/calib_corners.h"
#include "pipeline/gaussian_filter.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

std::vector<Eigen::Vector2d> TrueCorners(const Camera& cam, const Pose& pose) {
  std::vector<Eigen::Vector2d> out;
  for (const auto& q : Board().CornerPoints()) out.push_back(*cam.Project(pose * q));
  return out;
}

double RmsError(const CornerDetection& d, const std::vector<Eigen::Vector2d>& truth) {
  double s = 0;
  for (size_t k = 0; k < truth.size(); ++k) s += (d.corners[k] - truth[k]).squaredNorm();
  return std::sqrt(s / (2.0 * double(truth.size())));  // per axis
}

double MeanStd(const CornerDetection& d) {
  double s = 0;
  for (double v : d.corner_std_px) s += v;
  return s / double(d.corner_std_px.size());
}

std::vector<Pose> Poses() {
  return {BoardPose(0, 0, 0.20, 0, 0, 0),                  // frontal
          BoardPose(0.01, -0.005, 0.21, 35 * kDeg, 0, 0),   // tilted about x
          BoardPose(-0.01, 0.01, 0.22, 40 * kDeg, 50 * kDeg, 30 * kDeg),
          BoardPose(0.0, 0.0, 0.20, 25 * kDeg, 120 * kDeg, 180 * kDeg),  // upside down
          BoardPose(0.02, 0.015, 0.19, 20 * kDeg, 250 * kDeg, -75 * kDeg)};
}

TEST(CalibCorners, NoiseFreeBoardsToAFewHundredthsOfAPixel) {
  const Camera cam = CornerTestCamera();
  const auto poses = Poses();
  for (size_t v = 0; v < poses.size(); ++v) {
    const Image<float> img = RenderCheckerboard(cam, poses[v], Board());
    const CornerDetection d = DetectCheckerboard(img.View(), Board());
    ASSERT_TRUE(d.ok) << "pose " << v << ": " << d.reason;
    ASSERT_EQ(d.corners.size(), 70u);
    const auto truth = TrueCorners(cam, poses[v]);
    EXPECT_LT(RmsError(d, truth), 0.05) << "pose " << v;
    for (size_t k = 0; k < truth.size(); ++k) EXPECT_LT((d.corners[k] - truth[k]).norm(), 0.15) << "pose " << v << " corner " << k;
  }
}

TEST(CalibCorners, NoisyBoardsToATenthOfAPixel) {
  const Camera cam = CornerTestCamera();
  const auto poses = Poses();
  for (size_t v = 0; v < poses.size(); ++v) {
    SyntheticBoardOptions o;
    o.noise_sigma = 0.01 * (o.white - o.black);  // 1% of the contrast
    o.seed = 100 + v;
    const Image<float> img = RenderCheckerboard(cam, poses[v], Board(), o);
    const CornerDetection d = DetectCheckerboard(img.View(), Board());
    ASSERT_TRUE(d.ok) << "pose " << v << ": " << d.reason;
    EXPECT_LT(RmsError(d, TrueCorners(cam, poses[v])), 0.1) << "pose " << v;
    // The noise estimate finds the noise (a median over 300k pixels).
    EXPECT_NEAR(d.noise_sigma, o.noise_sigma, 0.1 * o.noise_sigma);
  }
}

// The predicted standard deviation matches the observed error where the noise
// dominates (5% noise: the synthetic image's own error, about 0.01 px RMS
// noise-free, adds less than 10% in quadrature). 280 corners give the RMS to
// about ±6% (two standard errors), hence the range.
TEST(CalibCorners, PredictedStdMatchesTheError) {
  const Camera cam = CornerTestCamera();
  const auto poses = Poses();
  double sum_err2 = 0, sum_std2 = 0;
  for (size_t v = 0; v < 4; ++v) {
    SyntheticBoardOptions o;
    o.noise_sigma = 0.05 * (o.white - o.black);
    o.seed = 200 + v;
    const Image<float> img = RenderCheckerboard(cam, poses[v], Board(), o);
    const CornerDetection d = DetectCheckerboard(img.View(), Board());
    ASSERT_TRUE(d.ok) << "pose " << v << ": " << d.reason;
    const double rms = RmsError(d, TrueCorners(cam, poses[v]));
    sum_err2 += rms * rms;
    sum_std2 += MeanStd(d) * MeanStd(d);
  }
  const double ratio = std::sqrt(sum_err2 / sum_std2);
  EXPECT_GT(ratio, 0.85);
  EXPECT_LT(ratio, 1.2);
}

// A defocused board under uneven light, as a real scanner sees it: the image
// blurred by a Gaussian of 1.2 px (isotropic blur keeps the corner's point
// symmetry) and lit from 100% down to 50% across the image (vignetting-like:
// a slow gradient shifts the saddle by a small fraction of the blur).
TEST(CalibCorners, BlurredUnevenlyLitBoard) {
  const Camera cam = CornerTestCamera();
  const Pose pose = Poses()[2];
  SyntheticBoardOptions o;
  o.noise_sigma = 0;
  const Image<float> sharp = RenderCheckerboard(cam, pose, Board(), o);
  const GaussianKernels k(1.2);
  const int w = sharp.width, h = sharp.height;
  Image<float> rows(w, h, 1), img(w, h, 1);  // separable: along rows, then columns
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double v = 0;
      for (int d = -k.radius; d <= k.radius; ++d) v += k.k0[size_t(d + k.radius)] * sharp.At(MirrorIndex(x + d, w), y);
      rows.At(x, y) = float(v);
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double v = 0;
      for (int d = -k.radius; d <= k.radius; ++d) v += k.k0[size_t(d + k.radius)] * rows.At(x, MirrorIndex(y + d, h));
      const double light = 1.0 - 0.5 * double(x) / w;
      img.At(x, y) = float(light * v + 0.01 * 0.8 * Rng::For(4, 0, uint64_t(y * w + x), 0).NextGaussian());
    }
  const CornerDetection d = DetectCheckerboard(img.View(), Board());
  ASSERT_TRUE(d.ok) << d.reason;
  EXPECT_LT(RmsError(d, TrueCorners(cam, pose)), 0.05);
}

TEST(CalibCorners, IntegerImagesAndChannels) {
  const Camera cam = CornerTestCamera();
  const Pose pose = Poses()[2];
  SyntheticBoardOptions o;
  o.noise_sigma = 0.01 * (o.white - o.black);
  const Image<float> img = RenderCheckerboard(cam, pose, Board(), o);
  const auto truth = TrueCorners(cam, pose);
  Image<uint8_t> u8(img.width, img.height, 1);
  Image<uint16_t> u16(img.width, img.height, 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double v = std::clamp(double(img.At(x, y)), 0.0, 1.0);
      u8.At(x, y) = uint8_t(std::lround(255 * v));
      for (int c = 0; c < 3; ++c) u16.At(x, y, c) = uint16_t(std::lround(4095 * v));
    }
  const CornerDetection d8 = DetectCheckerboard(u8.View(), Board());
  ASSERT_TRUE(d8.ok) << d8.reason;
  EXPECT_LT(RmsError(d8, truth), 0.1);
  const CornerDetection d16 = DetectCheckerboard(AnyImage(u16), Board());
  ASSERT_TRUE(d16.ok) << d16.reason;
  EXPECT_LT(RmsError(d16, truth), 0.1);
  // The noise estimate is in the image's own units.
  EXPECT_NEAR(d16.noise_sigma, 4095 * o.noise_sigma, 0.15 * 4095 * o.noise_sigma);
}

TEST(CalibCorners, RefusesAnImageWithoutABoard) {
  Image<float> flat(320, 240, 1, 0.5f);
  CornerDetection d = DetectCheckerboard(flat.View(), Board());
  EXPECT_FALSE(d.ok);
  EXPECT_NE(d.reason.find("no checkerboard"), std::string::npos) << d.reason;
  for (int y = 0; y < flat.height; ++y)
    for (int x = 0; x < flat.width; ++x) flat.At(x, y) += float(0.05 * Rng::For(1, 0, uint64_t(y * 320 + x), 0).NextGaussian());
  d = DetectCheckerboard(flat.View(), Board());
  EXPECT_FALSE(d.ok);
  EXPECT_TRUE(d.corners.empty());
}

TEST(CalibCorners, RefusesAPartlyVisibleBoard) {
  const Camera cam = CornerTestCamera();
  // Shifted right so that the last two columns of corners leave the image.
  const Image<float> img = RenderCheckerboard(cam, BoardPose(0.055, 0, 0.2, 0, 0, 0), Board());
  const CornerDetection d = DetectCheckerboard(img.View(), Board());
  EXPECT_FALSE(d.ok);
  EXPECT_NE(d.reason.find("partly outside"), std::string::npos) << d.reason;
  // The reason says where: the next corners beyond the grid lie past the
  // image's right edge (before, only "partly outside the image, occluded, or
  // too small or blurred").
  EXPECT_NE(d.reason.find("the grid runs off its right edge)"), std::string::npos) << d.reason;
  EXPECT_TRUE(d.corners.empty());
  // The visible corners are reported in the grid's own indices.
  EXPECT_GE(d.grid.size(), 7u * 7u);
  EXPECT_LT(d.grid.size(), 70u);
  // Off the right and bottom edges at once.
  const Image<float> corner = RenderCheckerboard(cam, BoardPose(0.055, 0.05, 0.2, 0, 0, 0), Board());
  const CornerDetection dc = DetectCheckerboard(corner.View(), Board());
  EXPECT_FALSE(dc.ok);
  EXPECT_NE(dc.reason.find("the grid runs off its right and bottom edges)"), std::string::npos) << dc.reason;
  // A board wholly inside the image with a corner hidden (a grey patch of
  // 30 px, the squares are 24) names no edge.
  Image<float> hidden = RenderCheckerboard(cam, BoardPose(0, 0, 0.2, 0, 0, 0), Board());
  const Eigen::Vector2d c = *cam.Project(BoardPose(0, 0, 0.2, 0, 0, 0) * Board().CornerPoints()[3 * 10 + 4]);
  for (int y = 0; y < hidden.height; ++y)
    for (int x = 0; x < hidden.width; ++x)
      if (std::abs(x - c.x()) < 15 && std::abs(y - c.y()) < 15) hidden.At(x, y) = 0.5f;
  const CornerDetection dh = DetectCheckerboard(hidden.View(), Board());
  EXPECT_FALSE(dh.ok);
  EXPECT_EQ(dh.reason.find("runs off"), std::string::npos) << dh.reason;
}

TEST(CalibCorners, RefusesABoardOfAnotherSize) {
  const Camera cam = CornerTestCamera();
  const Image<float> img = RenderCheckerboard(cam, Poses()[1], Board());
  CheckerboardSpec other = Board();
  other.rows = 5;
  other.cols = 8;
  const CornerDetection d = DetectCheckerboard(img.View(), other);
  EXPECT_FALSE(d.ok);
  EXPECT_EQ(d.grid.size(), 70u);
}

// Symmetric boards (refused before: rows + cols must be odd): a 7 x 9 board
// looks the same after a half turn, an 8 x 8 one after a quarter turn. Each
// is found in three poses, its corners in the order of one of those turned
// board frames (a right-handed frame, never a mirror image).
TEST(CalibCorners, SymmetricBoardsComeOutInATurnedBoardOrder) {
  const Camera cam = CornerTestCamera();
  for (const auto& [rows, cols] : {std::pair{7, 9}, std::pair{8, 8}}) {
    CheckerboardSpec b = Board();
    b.rows = rows, b.cols = cols;
    ASSERT_TRUE(b.Symmetric());
    for (size_t v : {1, 3, 4}) {  // tilted; upside down; turned by -75 degrees
      Pose pose = Poses()[v];
      // Board()'s centre moved to this board's.
      pose.translation() -= pose.linear() * Eigen::Vector3d(0.5 * (cols - 10) * b.square_m, 0.5 * (rows - 7) * b.square_m, 0);
      const CornerDetection d = DetectCheckerboard(RenderCheckerboard(cam, pose, b).View(), b);
      ASSERT_TRUE(d.ok) << rows << " x " << cols << " pose " << v << ": " << d.reason;
      ASSERT_EQ(d.corners.size(), size_t(rows * cols));
      // The board orders of the turns that map the board onto itself.
      std::vector<std::function<int(int, int)>> turns = {[&](int i, int j) { return i * cols + j; },
                                                         [&](int i, int j) { return (rows - 1 - i) * cols + (cols - 1 - j); }};
      if (rows == cols) {
        turns.push_back([&](int i, int j) { return j * cols + (cols - 1 - i); });
        turns.push_back([&](int i, int j) { return (rows - 1 - j) * cols + i; });
      }
      double best = 1e9;
      for (const auto& turn : turns) {
        double worst = 0;
        for (int i = 0; i < rows; ++i) {
          for (int j = 0; j < cols; ++j) {
            const Eigen::Vector2d truth = *cam.Project(pose * Eigen::Vector3d(j * b.square_m, i * b.square_m, 0));
            worst = std::max(worst, (d.corners[size_t(turn(i, j))] - truth).norm());
          }
        }
        best = std::min(best, worst);
      }
      EXPECT_LT(best, 0.15) << rows << " x " << cols << " pose " << v;
    }
  }
}

TEST(CalibCorners, OptionsAndBoardAreChecked) {
  Image<float> img(64, 48, 1, 0.5f);
  CheckerboardSpec small = Board();
  small.cols = 1;
  EXPECT_THROW(DetectCheckerboard(img.View(), small), InputError);
  CornerDetectionOptions o;
  o.sigma_px = 0.2;
  EXPECT_THROW(DetectCheckerboard(img.View(), Board(), o), InputError);
  Image<float> empty;
  EXPECT_THROW(DetectCheckerboard(empty.View(), Board()), InputError);
}

// The synthetic image itself: a frontal board on a pinhole camera, where a
// vertical edge falls at a known subpixel column; the pixel it crosses takes
// the area-weighted mean of the two colours.
TEST(CalibCorners, SyntheticBoardIsAreaAveraged) {
  const Camera cam = CornerTestCamera(false);
  const CheckerboardSpec b = Board();
  // Board at depth z, origin at camera point (x0, y0): board x maps to
  // u = cx + fx (x0 + x) / z. Place the edge x = 0 at u = 300.3.
  const double z = 0.2, u_edge = 300.3, v_row = 250.0;
  Pose pose = Pose::Identity();
  pose.translation() = Eigen::Vector3d((u_edge - cam.cx()) * z / cam.fx(), (v_row - cam.cy()) * z / cam.fy(), z);
  SyntheticBoardOptions o;
  const Image<float> img = RenderCheckerboard(cam, pose, b, o);
  // Row 253 lies in square row 0 (board y in [0, s]): left of the edge is
  // square (−1, 0) (white), right is square (0, 0) (black).
  const int y = 253;
  EXPECT_FLOAT_EQ(img.At(297, y), float(o.white));
  EXPECT_FLOAT_EQ(img.At(303, y), float(o.black));
  // Pixel 300 spans [299.5, 300.5]: 0.8 white, 0.2 black. Of the 16 x 16
  // jittered samples only the 16 in the column of strata the edge cuts are
  // uncertain, so the error stays below 1/16 of the contrast.
  const double expected = 0.8 * o.white + 0.2 * o.black;
  EXPECT_NEAR(img.At(300, y), expected, 0.05 * (o.white - o.black));
  // Off the board: the background.
  EXPECT_FLOAT_EQ(img.At(5, 5), float(o.background));
}

}  // namespace
}  // namespace lt

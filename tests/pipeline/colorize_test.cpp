// Colour for scan points from bright frames (pipeline/colorize.h): bilinear
// demosaicing against closed forms, the colour of a known-coloured target, and the
// laser contamination test from radiance images and from lit fractions.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/image_io.h"
#include "pipeline/colorize.h"

namespace lt {
namespace {

namespace fs = std::filesystem;

Camera SmallCamera() {
  CameraParams p;
  p.width = 40;
  p.height = 30;
  p.fx = p.fy = 400;
  p.cx = 19.5;
  p.cy = 14.5;
  return Camera(p);
}

// A linear function of position per colour channel.
double Linear(int c, double x, double y) { return 100.0 + 50.0 * c + (2.0 + c) * x + (3.0 - c) * y; }

TEST(SampleColour, BilinearDemosaicReproducesLinearColoursExactly) {
  // Each pixel holds its filter colour's linear function: bilinear interpolation on
  // each colour's lattice reproduces a linear function exactly, wherever the four
  // lattice neighbours exist (here: one lattice step inside the image).
  for (ColorFilter f : {ColorFilter::kRGGB, ColorFilter::kBGGR, ColorFilter::kGRBG, ColorFilter::kGBRG}) {
    Image<float> mosaic(20, 16, 1);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 20; ++x) mosaic.At(x, y) = float(Linear(FilterChannel(f, x, y), x, y));
    for (const Eigen::Vector2d& uv : {Eigen::Vector2d(5.3, 7.9), Eigen::Vector2d(2.0, 2.0), Eigen::Vector2d(16.7, 12.2)}) {
      const Eigen::Vector3d rgb = SampleColour(mosaic, f, uv);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], Linear(c, uv.x(), uv.y()), 1e-3) << int(f) << " " << c;
    }
  }
  // Mono and three-channel images: plain bilinear interpolation.
  Image<float> grey(10, 10, 1), rgb(10, 10, 3);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      grey.At(x, y) = float(Linear(0, x, y));
      for (int c = 0; c < 3; ++c) rgb.At(x, y, c) = float(Linear(c, x, y));
    }
  EXPECT_NEAR(SampleColour(grey, ColorFilter::kMono, {3.25, 4.5})[2], Linear(0, 3.25, 4.5), 1e-4);
  EXPECT_NEAR(SampleColour(rgb, ColorFilter::kMono, {3.25, 4.5})[1], Linear(1, 3.25, 4.5), 1e-4);
}

// A run folder: frames 0 (bright), 1 (dim), 2 (bright), all with the camera at the
// world origin looking along +z; the bright images are uniform RGGB mosaics.
struct ColourRun {
  fs::path dir = fs::temp_directory_path() / ("lt_colorize_" + std::to_string(::getpid()));
  std::vector<RunFrame> frames;
  ColourRun() {
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (int i = 0; i < 3; ++i) {
      RunFrame f;
      f.index = i;
      f.where = "manifest.jsonl:" + std::to_string(i + 1);
      f.laser_on = i == 1;
      f.laser_on_known = f.shutter_known = true;
      f.laser_fraction = i == 1 ? 1.0 : 0.0;
      f.world_from_cam = Pose::Identity();
      f.bit_depth = 10;
      f.png_bit_depth = 16;
      f.image = dir / ("frame" + std::to_string(i) + ".png");
      frames.push_back(f);
    }
  }
  ~ColourRun() { fs::remove_all(dir); }
  // A 16-bit PNG holding 10-bit DN: an RGGB mosaic of the colour rgb (DN).
  void WriteMosaic(int index, const Eigen::Vector3d& rgb) {
    Image<uint16_t> im(40, 30, 1);
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x) im.At(x, y) = uint16_t(rgb[FilterChannel(ColorFilter::kRGGB, x, y)]);
    WriteImage(frames[size_t(index)].image, im);
  }
};

TEST(Colorizer, KnownColourAveragedOverTheAdjacentBrightFrames) {
  ColourRun run;
  run.WriteMosaic(0, {800, 400, 100});
  run.WriteMosaic(2, {600, 200, 300});
  run.WriteMosaic(1, {0, 0, 0});
  // Black level 23 DN, full scale 1023 DN: colour = (mean DN - 23) / 1000 * 255.
  Colorizer colorizer(run.frames, SmallCamera(), ColorFilter::kRGGB, 23.0);
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0.1}, {0.004, -0.003, 0.1}, {1.0, 0, 0.1}, {0, 0, -0.1}};
  std::vector<PointColour> c = colorizer.Colour(1, points);
  ASSERT_EQ(c.size(), 4u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_TRUE(c[size_t(k)].coloured);
    EXPECT_FALSE(c[size_t(k)].contaminated);
    EXPECT_EQ(int(c[size_t(k)].rgb[0]), int(std::lround((700.0 - 23) / 1000 * 255)));  // 173
    EXPECT_EQ(int(c[size_t(k)].rgb[1]), int(std::lround((300.0 - 23) / 1000 * 255)));  // 71
    EXPECT_EQ(int(c[size_t(k)].rgb[2]), int(std::lround((200.0 - 23) / 1000 * 255)));  // 45
  }
  // Outside the image (x = 1 m at 0.1 m: 4000 px off) and behind the camera: uncoloured.
  EXPECT_FALSE(c[2].coloured);
  EXPECT_FALSE(c[3].coloured);
  EXPECT_EQ(colorizer.stats().coloured, 2);
  EXPECT_EQ(colorizer.stats().bright_frames, 2);
  EXPECT_EQ(colorizer.stats().contaminated, 0);
  EXPECT_FALSE(colorizer.stats().from_radiance);
}

// A moving scanner: each bright frame has its own pose, and a point takes its colour
// where that frame's camera saw it. The camera moves +4 mm along x from frame 0 to
// frame 2 (laser frame 1 in the middle); a point 0.1 m in front of the laser frame's
// camera lies 8 px right of the image centre in frame 0 (u = 27.5) and 8 px left in
// frame 2 (u = 11.5). Frame 0 is coloured only at u >= 24, frame 2 only at u <= 15:
// with each frame's own pose the point takes the mean of both colours; with the laser
// frame's pose it would sample the black centre (u = 19.5) of both.
TEST(Colorizer, EachBrightFrameIsSampledWithItsOwnPose) {
  ColourRun run;
  for (int i = 0; i < 3; ++i) run.frames[size_t(i)].world_from_cam->translation() = Eigen::Vector3d((i - 1) * 2e-3, 0, 0);
  auto write = [&](int index, const Eigen::Vector3d& rgb, int u_from, int u_to) {
    Image<uint16_t> im(40, 30, 1);
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x)
        im.At(x, y) = uint16_t(x >= u_from && x <= u_to ? rgb[FilterChannel(ColorFilter::kRGGB, x, y)] : 0.0);
    WriteImage(run.frames[size_t(index)].image, im);
  };
  write(0, {800, 400, 100}, 24, 39);
  write(2, {600, 200, 300}, 0, 15);
  write(1, {0, 0, 0}, 0, 39);
  Colorizer colorizer(run.frames, SmallCamera(), ColorFilter::kRGGB, 0.0);
  const std::vector<PointColour> c = colorizer.Colour(1, {{0, 0, 0.1}});
  ASSERT_TRUE(c[0].coloured);
  EXPECT_EQ(int(c[0].rgb[0]), int(std::lround(700.0 / 1023 * 255)));
  EXPECT_EQ(int(c[0].rgb[1]), int(std::lround(300.0 / 1023 * 255)));
  EXPECT_EQ(int(c[0].rgb[2]), int(std::lround(200.0 / 1023 * 255)));
}

// A structured-light frame (pattern projector on, laser and LED off) is no
// colour frame: the point takes frame 0's colour alone, and a flood-lit frame
// after the pattern frame is the one used on that side. Before, the pattern
// frame was taken as the next bright frame (a rendered run with a pattern
// projector frame coloured every point with the pattern and called 87.5% of
// them contaminated by laser light, since its radiance is in the laser channel).
TEST(Colorizer, PatternFramesGiveNoColour) {
  ColourRun run;
  run.WriteMosaic(0, {800, 400, 100});
  run.WriteMosaic(2, {0, 900, 0});
  run.WriteMosaic(1, {0, 0, 0});
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0.1}};
  for (bool commanded : {true, false}) {
    std::vector<RunFrame> frames = run.frames;
    if (commanded) {
      frames[2].pattern_on = frames[2].pattern_on_known = true;
    } else {
      frames[2].pattern_fraction = 1.0;  // only the lit fraction says so
    }
    EXPECT_TRUE(frames[2].IsPatternFrame());
    EXPECT_FALSE(frames[2].IsColourFrame());
    Colorizer colorizer(frames, SmallCamera(), ColorFilter::kRGGB, 23.0);
    std::vector<PointColour> c = colorizer.Colour(1, points);
    ASSERT_TRUE(c[0].coloured);
    EXPECT_EQ(int(c[0].rgb[0]), int(std::lround((800.0 - 23) / 1000 * 255)));
    EXPECT_EQ(int(c[0].rgb[1]), int(std::lround((400.0 - 23) / 1000 * 255)));
    EXPECT_EQ(colorizer.stats().bright_frames, 1);
  }
  // A flood-lit frame beyond the pattern frame gives the colour on that side.
  std::vector<RunFrame> frames = run.frames;
  frames[2].pattern_on = frames[2].pattern_on_known = true;
  RunFrame after = run.frames[0];
  after.index = 3;
  after.image = run.dir / "frame3.png";
  frames.push_back(after);
  run.frames.push_back(after);
  run.WriteMosaic(3, {600, 200, 300});
  Colorizer colorizer(frames, SmallCamera(), ColorFilter::kRGGB, 23.0);
  std::vector<PointColour> c = colorizer.Colour(1, points);
  EXPECT_EQ(int(c[0].rgb[0]), int(std::lround((700.0 - 23) / 1000 * 255)));
  EXPECT_EQ(colorizer.stats().bright_frames, 2);
}

TEST(Colorizer, ContaminationFromLitFractionOrRadiance) {
  ColourRun run;
  for (int i = 0; i < 3; ++i) run.WriteMosaic(i, {500, 500, 500});
  const std::vector<Eigen::Vector3d> points = {{-0.002, 0, 0.1}, {0.002, 0, 0.1}};  // u = 11.5 and 27.5 px
  {
    // No radiance image: the laser lit 10% of bright frame 2's exposure.
    std::vector<RunFrame> frames = run.frames;
    frames[2].laser_fraction = 0.1;
    Colorizer colorizer(frames, SmallCamera(), ColorFilter::kRGGB, 0.0);
    std::vector<PointColour> c = colorizer.Colour(1, points);
    EXPECT_TRUE(c[0].contaminated && c[1].contaminated);
    EXPECT_EQ(colorizer.stats().contaminated, 2);
  }
  {
    // Radiance images: laser light in the right half of frame 2 only, at 10% and
    // 1% of the broadband radiance (the threshold is 5%).
    std::vector<RunFrame> frames = run.frames;
    for (int i : {0, 2}) {
      Image<float> radiance(40, 30, 4, 0.0f);
      for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
          for (int c = 0; c < 3; ++c) radiance.At(x, y, c) = 2.0f;
          radiance.At(x, y, 3) = i == 2 && x >= 20 ? 0.2f : i == 2 ? 0.02f : 0.0f;
        }
      frames[size_t(i)].radiance = run.dir / ("radiance" + std::to_string(i) + ".exr");
      WriteImage(*frames[size_t(i)].radiance, radiance, true, {"R", "G", "B", "laser"});
    }
    Colorizer colorizer(frames, SmallCamera(), ColorFilter::kRGGB, 0.0);
    std::vector<PointColour> c = colorizer.Colour(1, points);
    EXPECT_FALSE(c[0].contaminated);
    EXPECT_TRUE(c[1].contaminated);
    EXPECT_TRUE(colorizer.stats().from_radiance);
    EXPECT_EQ(colorizer.stats().contaminated, 1);
  }
}

TEST(Colorizer, ErrorsNameTheBrightFrame) {
  ColourRun run;
  run.WriteMosaic(0, {1, 2, 3});
  // Frame 2's image is missing.
  Colorizer colorizer(run.frames, SmallCamera(), ColorFilter::kRGGB, 0.0);
  try {
    colorizer.Colour(1, {{0, 0, 0.1}});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("frame2.png"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("bright frame 2"));
  }
  ColourOptions bad;
  bad.contamination_ratio = 0;
  EXPECT_THROW(bad.Check(), InputError);
}

}  // namespace
}  // namespace lt

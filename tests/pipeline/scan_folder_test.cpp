// ScanRun on a capture without a manifest: a folder of images in file name
// order (pipeline/capture_folder.h), stitched with a pose file
// (pipeline/pose_file.h); the world points against the closed form
// world_from_cam · p_in_cam of the synthetic runs of scan_test_util.h.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/pose_trajectory.h"
#include "pipeline/capture_folder.h"
#include "pipeline/image_folder.h"
#include "scan_test_util.h"

namespace lt {
namespace {

using namespace scan_test;
using ::testing::HasSubstr;
using ::testing::Not;

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

Pose FramePose(int k) {
  Pose p = Pose::Identity();
  p.linear() = Eigen::AngleAxisd(0.3 + 0.5 * k, Eigen::Vector3d(0.1, 1, -0.3 * k).normalized()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(0.2 + 0.1 * k, -0.05 * k, 0.4);
  return p;
}

// A pose file "x,y,z,qx,qy,qz,qw" in millimetres (a header unit) for frames 0..n-1.
fs::path WritePoses(const fs::path& path, int n, double scale = 1000) {
  std::ofstream out(path);
  out << "t,x [mm],y [mm],z [mm],qx,qy,qz,qw\n";
  out.precision(17);
  for (int k = 0; k < n; ++k) {
    const Pose p = FramePose(k);
    const Eigen::Quaterniond q(p.linear());
    const Eigen::Vector3d t = p.translation() * scale;
    out << 0.1 * k << "," << t.x() << "," << t.y() << "," << t.z() << "," << q.x() << "," << q.y() << "," << q.z()
        << "," << q.w() << "\n";
  }
  return path;
}

// The synthetic run turned into a capture without a manifest: its laser frame
// (10-bit DN in 16-bit PNGs) saved as frames/img1.png, img2.png, img10.png.
SyntheticRun MakeCapture(const std::string& name) {
  SyntheticRun run = MakeRun(name, 1);
  fs::remove(run.dir / "manifest.jsonl");
  for (const char* n : {"img1.png", "img2.png", "img10.png"}) fs::copy_file(run.dir / "frames/000000.png", run.dir / "frames" / n);
  fs::remove(run.dir / "frames/000000.png");
  return run;
}

void ExpectWorldPoints(const SyntheticRun& run, int frames, const Pose& cam_from_pose_frame) {
  for (int k = 0; k < frames; ++k) {
    const std::vector<ScanPoint> points = ReadScanCsv(run.dir / ScanCentersName(k));
    ASSERT_GE(points.size(), 150u) << k;
    for (const ScanPoint& p : points) {
      ASSERT_TRUE(p.p_in_cam && p.p_in_world);
      EXPECT_LT(ErrorInPixels(run, 0, p), 0.01);
      const Eigen::Vector3d exact = FramePose(k) * cam_from_pose_frame * *p.p_in_cam;
      EXPECT_LT((*p.p_in_world - exact).norm(), 1e-9) << k;
    }
  }
}

TEST(CaptureFolder, FramesAreTheImagesInNaturalOrder) {
  EXPECT_TRUE(NaturalLess("img2.png", "img10.png"));
  EXPECT_FALSE(NaturalLess("img10.png", "img2.png"));
  EXPECT_TRUE(NaturalLess("frame_0009.png", "frame_0010.png"));
  EXPECT_TRUE(NaturalLess("IMG3.PNG", "img4.png"));
  EXPECT_TRUE(NaturalLess("a.png", "a1.png"));
  EXPECT_NE(NaturalLess("img01.png", "img1.png"), NaturalLess("img1.png", "img01.png"));  // a total order
  const fs::path dir = fs::temp_directory_path() / ("lt_capture_folder_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  const Image<uint8_t> img(4, 3, 1, 7);
  for (const char* n : {"img10.png", "img2.PNG", "img1.tif", ".hidden.png", "._img3.png", "sub/img0.png"}) WriteImage(dir / n, img);
  for (const char* n : {"Thumbs.db", ".DS_Store", "notes.txt"}) std::ofstream(dir / n) << "x";
  const ScanFrames listed = ReadScanFrames(dir);
  EXPECT_TRUE(listed.from_listing);
  EXPECT_EQ(listed.source, dir);
  ASSERT_EQ(listed.frames.size(), 3u);
  EXPECT_EQ(listed.frames[0].image, dir / "img1.tif");
  EXPECT_EQ(listed.frames[1].image, dir / "img2.PNG");
  EXPECT_EQ(listed.frames[2].image, dir / "img10.png");
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(listed.frames[size_t(k)].index, k);
    EXPECT_TRUE(listed.frames[size_t(k)].IsLaserFrame());
  }
  EXPECT_EQ(listed.width, 4);
  // Images both directly and in frames/: which are the frames?
  fs::create_directories(dir / "frames");
  WriteImage(dir / "frames/0.png", img);
  EXPECT_THAT(ErrorOf([&] { ReadScanFrames(dir); }), HasSubstr(dir.string() + ": holds images both directly"));
  for (const char* n : {"img10.png", "img2.PNG", "img1.tif"}) fs::remove(dir / n);
  EXPECT_EQ(ReadScanFrames(dir).source, dir / "frames");
  // Mixed sizes name the odd image and the first.
  WriteImage(dir / "frames/1.png", Image<uint8_t>(5, 3, 1, 7));
  EXPECT_THAT(ErrorOf([&] { ReadScanFrames(dir); }),
              HasSubstr((dir / "frames/1.png").string() + ": the image is 5x3 but 0.png, the first frame, is 4x3"));
  // No image at all.
  fs::remove_all(dir / "frames");
  EXPECT_THAT(ErrorOf([&] { ReadScanFrames(dir); }), HasSubstr(dir.string() + ": no manifest.jsonl and no image file"));
  fs::remove_all(dir);
}

// Three frames and a pose file in millimetres: the poses are the camera's, the
// world points world_from_cam · p_in_cam; the 10-bit DN need the bit depth.
TEST(ScanFolder, FramesWithAPoseFileAreStitchedInTheWorld) {
  SyntheticRun run = MakeCapture("folder_poses");
  nlohmann::json rig = nlohmann::json::parse(std::ifstream(run.dir / "rig.json"));
  rig["image_sensor"].erase("bit_depth");  // the camera's software wrote 10-bit DN in 16-bit PNGs, unsaid
  std::ofstream(run.dir / "rig.json") << rig.dump(2);
  ScanOptions o;
  o.poses = WritePoses(run.dir / "poses.csv", 3);
  std::vector<std::string> warnings;
  ScanSummary none = ScanRun(run.dir, o, [&](const std::string& w) { warnings.push_back(w); });  // 10% of 65535
  EXPECT_EQ(none.triangulated, 0);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("no stripe point in a 16-bit image of unknown bit depth"));
  EXPECT_THAT(warnings[0], HasSubstr("fits in 10 bits; a 10- or 12-bit camera's frames need --bit-depth"));
  o.bit_depth = 10;
  ScanSummary s = ScanRun(run.dir, o);
  EXPECT_TRUE(s.frames_from_listing);
  EXPECT_EQ(s.frames_source, run.dir / "frames");
  EXPECT_EQ(s.laser_frames, 3);
  EXPECT_TRUE(s.world_frame);
  EXPECT_THAT(s.pose_source, HasSubstr("world_from_cam from " + o.poses->string()));
  EXPECT_THAT(s.pose_source, HasSubstr("mm"));
  ExpectWorldPoints(run, 3, Pose::Identity());
  EXPECT_EQ(ReadPly(run.dir / "cloud.ply").points.size(), size_t(s.triangulated));
}

// Frames saved with an alpha channel (grey + alpha, as some camera software and
// image editors write PNGs) scan as the grey frames they are, as `extract` reads
// them: the alpha is coverage, not light. Before, "the image has 2 channels".
TEST(ScanFolder, FramesWithAnAlphaChannelScanAsGrey) {
  SyntheticRun run = MakeCapture("folder_alpha");
  for (const char* n : {"img1.png", "img2.png", "img10.png"}) {
    const fs::path path = run.dir / "frames" / n;
    const Image<uint16_t> grey = std::get<Image<uint16_t>>(ReadImage(path));
    Image<uint16_t> with_alpha(grey.width, grey.height, 2);
    for (int y = 0; y < grey.height; ++y) {
      for (int x = 0; x < grey.width; ++x) {
        with_alpha.At(x, y, 0) = grey.At(x, y, 0);
        with_alpha.At(x, y, 1) = 65535;
      }
    }
    WriteImage(path, with_alpha);
    ASSERT_EQ(ReadImageFileSize(path).channels, 2);
  }
  ScanOptions o;
  o.poses = WritePoses(run.dir / "poses.csv", 3);
  o.bit_depth = 10;
  ScanSummary s = ScanRun(run.dir, o);
  EXPECT_EQ(s.laser_frames, 3);
  ExpectWorldPoints(run, 3, Pose::Identity());
}

// With a calibration file's hand-eye pose the file gives the tool's poses:
// world = world_from_tool · tool_from_cam · p_in_cam.
TEST(ScanFolder, PoseFileGivesToolPosesWithAHandEyeCalibration) {
  SyntheticRun run = MakeCapture("folder_hand_eye");
  fs::remove(run.dir / "rig.json");
  CalibrationFile cal;
  cal.camera = CalibratedCamera::From(run.camera);
  cal.laser_planes = run.sheets;
  Pose tool_from_cam = Pose::Identity();
  tool_from_cam.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 0, 0.3).normalized()).toRotationMatrix();
  tool_from_cam.translation() = Eigen::Vector3d(0.01, -0.02, 0.05);
  cal.tool_from_cam = tool_from_cam;
  ScanOptions o;
  o.calibration = run.dir / "calib.yml";
  WriteCalibrationFile(*o.calibration, cal);
  o.poses = WritePoses(run.dir / "robot.csv", 3);
  o.bit_depth = 10;
  std::vector<std::string> warnings;
  ScanSummary s = ScanRun(run.dir, o, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_THAT(s.pose_source, HasSubstr("world_from_tool from " + o.poses->string()));
  EXPECT_THAT(s.pose_source, HasSubstr("tool_from_cam of " + o.calibration->string()));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("its bit depth --bit-depth's"));
  ExpectWorldPoints(run, 3, tool_from_cam);
}

// Alternating laser and LED-lit frames without a manifest: --shutter
// alternate says which are which, and the bright ones colour the cloud.
TEST(ScanFolder, AlternatingShutterGivesColourFromTheBrightFrames) {
  SyntheticRun run = MakeRun("folder_alternate", 1);  // rig.json: a 12-bit sensor
  fs::remove(run.dir / "manifest.jsonl");
  const Image<uint16_t> bright(160, 120, 1, 500);  // the LED-lit scene, 500 DN
  for (const char* n : {"f1.png", "f3.png"}) fs::copy_file(run.dir / "frames/000000.png", run.dir / "frames" / n);
  for (const char* n : {"f2.png", "f4.png"}) WriteImage(run.dir / "frames" / n, bright);
  fs::remove(run.dir / "frames/000000.png");
  ScanOptions o;
  o.poses = run.dir / "poses.csv";
  std::ofstream(*o.poses) << "x,y,z,qx,qy,qz,qw\n" << std::string(4, ' ') << "\n0.1,0.2,0.3,0,0,0,1\n0.1,0.2,0.3,0,0,0,1\n"
                          << "0.1,0.2,0.3,0,0,0,1\n0.1,0.2,0.3,0,0,0,1\n";
  std::vector<std::string> warnings;
  auto warn = [&](const std::string& w) { warnings.push_back(w); };
  ScanSummary all = ScanRun(run.dir, o, warn);  // every frame a laser frame
  EXPECT_EQ(all.laser_frames, 4);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("2 frames (1, 3) of a capture without a manifest have most pixels above"));
  EXPECT_THAT(warnings[0], HasSubstr("--shutter alternate"));
  warnings.clear();
  o.shutter = ShutterPattern::kAlternateBrightFirst;  // the wrong phase
  ScanRun(run.dir, o, warn);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("2 frames (1, 3) scanned as laser frames by --shutter alternate-bright-first"));
  warnings.clear();
  o.shutter = ShutterPattern::kAlternateLaserFirst;
  ScanSummary s = ScanRun(run.dir, o, warn);
  EXPECT_TRUE(warnings.empty()) << warnings[0];
  EXPECT_EQ(s.laser_frames, 2);
  EXPECT_EQ(s.other_frames, 2);
  ASSERT_TRUE(s.coloured);
  EXPECT_EQ(s.colour.bright_frames, 2);
  EXPECT_EQ(s.colour.coloured, s.colour.points);
  EXPECT_EQ(s.colour.contaminated, 0);
  // The bright frames' centres of the first scan (every frame a laser frame) are gone.
  for (int k : {1, 3}) EXPECT_FALSE(fs::exists(run.dir / ScanCentersName(k))) << k;
  EXPECT_TRUE(fs::exists(run.dir / ScanCentersName(2)));
  const PointCloud cloud = ReadPly(run.dir / "cloud.ply");
  ASSERT_TRUE(cloud.has_colour);
  ASSERT_EQ(cloud.points.size(), size_t(s.triangulated));
  const uint8_t grey = uint8_t(std::lround(500.0 / 4095 * 255));
  for (const CloudPoint& p : cloud.points) EXPECT_EQ(p.rgb, (std::array<uint8_t, 3>{grey, grey, grey}));
}

// A tracker's log at its own rate (TUM, more poses than frames) and images
// named by their time: each frame takes the pose interpolated at its time.
TEST(ScanFolder, PosesAreInterpolatedAtTheImagesTimes) {
  SyntheticRun run = MakeRun("folder_times", 1);
  fs::remove(run.dir / "manifest.jsonl");
  // Natural order would put 100.3 before 100.25: names that are numbers go by value.
  const std::vector<std::string> names = {"100.05", "100.25", "100.3"};
  for (const std::string& n : names) fs::copy_file(run.dir / "frames/000000.png", run.dir / "frames" / (n + ".png"));
  fs::remove(run.dir / "frames/000000.png");
  std::vector<PoseSample> samples;
  std::ofstream tum(run.dir / "groundtruth.txt");
  tum << "# timestamp tx ty tz qx qy qz qw\n";
  tum.precision(17);
  for (int k = 0; k < 5; ++k) {
    const Pose p = FramePose(k);
    const Eigen::Quaterniond q(p.linear());
    samples.push_back({100 + 0.1 * k, p.translation(), q});
    tum << 100 + 0.1 * k << " " << p.translation().x() << " " << p.translation().y() << " " << p.translation().z()
        << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w() << "\n";
  }
  tum.close();
  const PoseTrajectory truth(samples);
  ScanOptions o;
  o.poses = run.dir / "groundtruth.txt";
  ScanSummary s = ScanRun(run.dir, o);
  EXPECT_THAT(s.pose_source, HasSubstr("(CSV columns timestamp,tx,ty,tz,qx,qy,qz,qw, m, interpolated at the images' times)"));
  ASSERT_EQ(s.laser_frames, 3);
  for (int k = 0; k < 3; ++k) {
    const Pose expected = truth.At(std::stod(names[size_t(k)]));
    const std::vector<ScanPoint> points = ReadScanCsv(run.dir / ScanCentersName(k));
    ASSERT_GE(points.size(), 150u);
    for (const ScanPoint& p : points) EXPECT_LT((*p.p_in_world - expected * *p.p_in_cam).norm(), 1e-9) << k;
  }
  // Names in nanoseconds match the seconds of the log too.
  for (int k = 0; k < 3; ++k) {
    const std::string ns = std::to_string(std::llround(std::stod(names[size_t(k)]) * 1e9));
    fs::rename(run.dir / "frames" / (names[size_t(k)] + ".png"), run.dir / "frames" / (ns + ".png"));
  }
  ScanRun(run.dir, o);
  const Pose expected = truth.At(100.25);
  for (const ScanPoint& p : ReadScanCsv(run.dir / ScanCentersName(1))) {
    EXPECT_LT((*p.p_in_world - expected * *p.p_in_cam).norm(), 1e-9);
  }
  // A name outside the log's times: the counts must match.
  fs::copy_file(run.dir / "frames/100050000000.png", run.dir / "frames/100500000000.png");
  EXPECT_THAT(ErrorOf([&] { ScanRun(run.dir, o); }),
              HasSubstr(o.poses->string() + ": holds 5 poses but " + (run.dir / "frames").string() + " has 4 frames"));
}

// Zero-padded frame numbers ("000003.png", as renderers and frame grabbers
// write them) are not times: read as milliseconds, 0..3 lie within a log that
// starts at 0 s, and each frame took the pose interpolated at that many ms.
TEST(ScanFolder, ZeroPaddedFrameNumbersAreNotTimes) {
  SyntheticRun run = MakeRun("folder_numbers", 1);
  fs::remove(run.dir / "manifest.jsonl");
  for (const char* n : {"000001.png", "000002.png", "000003.png"})
    fs::copy_file(run.dir / "frames/000000.png", run.dir / "frames" / n);
  ScanOptions o;
  o.poses = WritePoses(run.dir / "poses.csv", 2);  // times 0 and 0.1 s
  EXPECT_THAT(ErrorOf([&] { ScanRun(run.dir, o); }),
              HasSubstr(o.poses->string() + ": holds 2 poses but " + (run.dir / "frames").string() + " has 4 frames"));
  // With the counts equal, frame k takes row k.
  o.poses = WritePoses(run.dir / "poses.csv", 4);
  ScanSummary s = ScanRun(run.dir, o);
  EXPECT_THAT(s.pose_source, Not(HasSubstr("interpolated")));
  for (int k = 0; k < 4; ++k) {
    for (const ScanPoint& p : ReadScanCsv(run.dir / ScanCentersName(k)))
      EXPECT_LT((*p.p_in_world - FramePose(k) * *p.p_in_cam).norm(), 1e-9) << k;
  }
}

// --image-time-offset: a camera stamping the start of its exposure names each
// image half an exposure before the time its pose belongs to; the offset
// matches every frame by time, also when the counts agree.
TEST(ScanFolder, ImageTimeOffsetShiftsTheMatchedTimes) {
  SyntheticRun run = MakeRun("folder_time_offset", 1);
  fs::remove(run.dir / "manifest.jsonl");
  const std::vector<double> names = {100.05, 100.25};
  for (double n : names) fs::copy_file(run.dir / "frames/000000.png", run.dir / "frames" / (FormatNumber(n) + ".png"));
  fs::remove(run.dir / "frames/000000.png");
  std::vector<PoseSample> samples;
  std::ofstream csv(run.dir / "poses.csv");
  csv << "t,x,y,z,qx,qy,qz,qw\n";
  csv.precision(17);
  for (int k = 0; k < 2; ++k) {  // as many poses as frames: without the offset they go by order
    const Pose p = FramePose(k);
    const Eigen::Quaterniond q(p.linear());
    samples.push_back({100 + 0.3 * k, p.translation(), q});
    csv << 100 + 0.3 * k << "," << p.translation().x() << "," << p.translation().y() << "," << p.translation().z()
        << "," << q.x() << "," << q.y() << "," << q.z() << "," << q.w() << "\n";
  }
  csv.close();
  const PoseTrajectory truth(samples);
  ScanOptions o;
  o.poses = run.dir / "poses.csv";
  o.pose_file.image_time_offset_s = 0.02;
  ScanSummary s = ScanRun(run.dir, o);
  EXPECT_THAT(s.pose_source, HasSubstr("interpolated at the images' times + 0.02 s"));
  for (int k = 0; k < 2; ++k) {
    const Pose expected = truth.At(names[size_t(k)] + 0.02);
    const std::vector<ScanPoint> points = ReadScanCsv(run.dir / ScanCentersName(k));
    ASSERT_GE(points.size(), 150u);
    for (const ScanPoint& p : points) EXPECT_LT((*p.p_in_world - expected * *p.p_in_cam).norm(), 1e-9) << k;
  }
  // Shifted past the file's last time: an error naming the file and its times.
  o.pose_file.image_time_offset_s = 0.1;
  EXPECT_THAT(ErrorOf([&] { ScanRun(run.dir, o); }),
              HasSubstr(o.poses->string() + ": --image-time-offset matches poses to the images' times, but " +
                        (run.dir / "frames").string() + "'s image names are not all times within the file's, 100 to 100.3 s"));
}

// A run with a manifest: the pose file replaces its world_from_cam.
TEST(ScanFolder, PoseFileReplacesTheManifestsPoses) {
  SyntheticRun run = MakeRun("manifest_poses", 1);  // frames 0 (laser) and 1 (bright)
  WriteImage(run.dir / "frames/000001.png", Image<uint16_t>(160, 120, 1, 500));  // posed now: it gives colour
  ScanOptions o;
  o.poses = WritePoses(run.dir / "poses.csv", 2);
  ScanSummary s = ScanRun(run.dir, o);
  EXPECT_FALSE(s.frames_from_listing);
  ExpectWorldPoints(run, 1, Pose::Identity());
}

// Bad input: a clear error naming the file (and line, counts), nothing written.
TEST(ScanFolder, BadInputWritesNothing) {
  SyntheticRun run = MakeCapture("folder_bad");
  ScanOptions o;
  o.bit_depth = 10;
  o.poses = WritePoses(run.dir / "poses.csv", 2);
  auto nothing_written = [&] {
    EXPECT_FALSE(fs::exists(run.dir / "centers"));
    EXPECT_FALSE(fs::exists(run.dir / "cloud.ply"));
  };
  EXPECT_THAT(ErrorOf([&] { ScanRun(run.dir, o); }),
              HasSubstr(o.poses->string() + ": holds 2 poses but " + (run.dir / "frames").string() + " has 3 frames"));
  nothing_written();
  std::ofstream(*o.poses, std::ios::app) << "0.3,1,2,3,0,0,0,0.5\n";
  EXPECT_THAT(ErrorOf([&] { ScanRun(run.dir, o); }),
              HasSubstr(o.poses->string() + ":4: the quaternion must have unit norm"));
  nothing_written();
  o.poses.reset();
  WriteImage(run.dir / "frames/img11.png", Image<uint16_t>(80, 60, 1, 0));
  EXPECT_THAT(ErrorOf([&] { ScanRun(run.dir, o); }),
              HasSubstr((run.dir / "frames/img11.png").string() + ": the image is 80x60 but img1.png"));
  nothing_written();
  // Every image of another size than the camera's.
  for (const char* n : {"img1.png", "img2.png", "img10.png"}) fs::remove(run.dir / "frames" / n);
  EXPECT_THAT(ErrorOf([&] { ScanRun(run.dir, o); }),
              HasSubstr((run.dir / "frames/img11.png").string() + ": the image is 80x60 but the camera"));
  nothing_written();
}

}  // namespace
}  // namespace lt

// ScanRun on runs as a real capture delivers them: manifests without bit depth or
// shutter keys, no rig.json, Bayer frames named by an option, data in the top bits,
// and a scan stopped by a bad frame (the synthetic runs of scan_test_util.h).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scan_test_util.h"

namespace lt {
namespace {

using namespace scan_test;
using ::testing::HasSubstr;

// A capture tool's manifest gives no bit_depth: the image sensor's (rig.json)
// sets the default threshold, 10% of 1023 for 10-bit DN in 16-bit PNGs, not
// 10% of 65535 (above the stripe's 1000 DN: no point was found).
TEST(Scan, ManifestWithoutBitDepthTakesTheRigsBitDepth) {
  SyntheticRun run = MakeRun("rig_bits", 1);
  nlohmann::json rig = nlohmann::json::parse(std::ifstream(run.dir / "rig.json"));
  rig["image_sensor"]["bit_depth"] = 10;
  std::ofstream(run.dir / "rig.json") << rig.dump(2);
  std::ofstream(run.dir / "manifest.jsonl") << R"({"index":0,"files":{"image":"frames/000000.png"}})" << "\n";
  ScanSummary s = ScanRun(run.dir, ScanOptions{});
  EXPECT_GE(s.triangulated, 150);
  for (const ScanPoint& p : ReadScanCsv(run.dir / "centers/000000.csv")) {
    ASSERT_TRUE(p.p_in_cam);
    EXPECT_LT(ErrorInPixels(run, 0, p), 0.01);
  }
}

// A real capture has no rig.json: the calibration file's camera (lasertwin
// calibrate's) is the camera, its laser planes the planes.
TEST(Scan, CaptureWithoutRigTakesTheCalibrationFilesCamera) {
  SyntheticRun run = MakeRun("calib_only", 1);
  fs::remove(run.dir / "rig.json");
  ScanOptions o;
  try {
    ScanRun(run.dir, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("holds neither rig.json nor scene.json"));
    EXPECT_THAT(e.what(), HasSubstr("scan --calib"));
  }
  CalibrationFile cal;
  cal.camera = CalibratedCamera::From(run.camera);
  cal.laser_planes = run.sheets;
  const fs::path file = run.dir / "calib.yml";
  WriteCalibrationFile(file, cal);
  o.calibration = file;
  std::vector<std::string> warnings;
  ScanSummary s = ScanRun(run.dir, o, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_EQ(s.plane_source, file);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("holds no rig.json: the camera is " + file.string() + "'s"));
  EXPECT_THAT(warnings[0], HasSubstr("mono (--bayer sets a mosaic)"));
  EXPECT_TRUE(s.world_frame);
  std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_GE(points.size(), 150u);
  for (const ScanPoint& p : points) {
    ASSERT_TRUE(p.p_in_cam);
    EXPECT_LT(ErrorInPixels(run, 0, p), 0.01);
  }
  // A calibration file without a camera part cannot stand in for the rig.
  cal.camera.reset();
  WriteCalibrationFile(file, cal);
  EXPECT_THROW(ScanRun(run.dir, o), InputError);
}

// A colour sensor's capture without rig.json (the calibration file's camera):
// color_filter (--bayer) says the frames are raw mosaics; the points are those
// of the same run whose rig.json gives the mosaic.
TEST(Scan, ColorFilterOptionGivesTheMosaicOfARigFromACalibrationFile) {
  SyntheticRun run = MakeRun("bayer_calib", 1, false, ColorFilter::kRGGB);
  ScanOptions o;
  o.extraction.channel_weights = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  ScanRun(run.dir, o);
  const std::vector<ScanPoint> with_rig = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_GE(with_rig.size(), 150u);
  fs::remove(run.dir / "rig.json");
  CalibrationFile cal;
  cal.camera = CalibratedCamera::From(run.camera);
  cal.laser_planes = run.sheets;
  WriteCalibrationFile(run.dir / "calib.yml", cal);
  o.calibration = run.dir / "calib.yml";
  o.color_filter = ColorFilter::kRGGB;
  ScanRun(run.dir, o);
  const std::vector<ScanPoint> with_option = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_EQ(with_option.size(), with_rig.size());
  for (size_t i = 0; i < with_rig.size(); ++i) {
    EXPECT_EQ(with_option[i].pixel.u, with_rig[i].pixel.u);
    EXPECT_EQ(with_option[i].pixel.v, with_rig[i].pixel.v);
  }
}

// Alternating bright and laser frames recorded without shutter keys are all
// scanned as laser frames; the flood-lit ones are named in a warning.
TEST(Scan, FloodLitFramesWithoutShutterKeysAreWarned) {
  SyntheticRun run = MakeRun("no_shutter", 1);
  WriteImage(run.dir / "frames/000001.png", Image<uint16_t>(160, 120, 1, 500));  // LED-lit scene, 500 of 1023 DN
  std::ofstream(run.dir / "manifest.jsonl")
      << R"({"index":0,"files":{"image":"frames/000000.png"},"bit_depth":10})" << "\n"
      << R"({"index":1,"files":{"image":"frames/000001.png"},"bit_depth":10})" << "\n";
  std::vector<std::string> warnings;
  ScanSummary s = ScanRun(run.dir, ScanOptions{}, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_EQ(s.laser_frames, 2);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("1 frame (1) with no shutter.laser_on in the manifest have most pixels above"));
  // With the shutter state the bright frame is skipped, and nothing is said.
  std::ofstream(run.dir / "manifest.jsonl")
      << R"({"index":0,"shutter":{"laser_on":true},"files":{"image":"frames/000000.png"},"bit_depth":10})" << "\n"
      << R"({"index":1,"shutter":{"laser_on":false},"files":{"image":"frames/000001.png"},"bit_depth":10})" << "\n";
  warnings.clear();
  s = ScanRun(run.dir, ScanOptions{}, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_EQ(s.laser_frames, 1);
  EXPECT_TRUE(warnings.empty());
}

// 10-bit DN stored in the top bits of a 16-bit PNG (MSB-aligned) while the
// manifest says bit_depth 10: the samples above 1023 are named in a warning.
TEST(Scan, SamplesAboveTheBitDepthAreWarned) {
  SyntheticRun run = MakeRun("msb_aligned", 1);
  std::vector<std::string> warnings;
  ScanRun(run.dir, ScanOptions{}, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_TRUE(warnings.empty());
  AnyImage any = ReadImage(run.dir / "frames/000000.png");
  Image<uint16_t>& im = std::get<Image<uint16_t>>(any);
  for (uint16_t& v : im.pixels) v = uint16_t(v << 6);
  WriteImage(run.dir / "frames/000000.png", im);
  ScanRun(run.dir, ScanOptions{}, [&](const std::string& w) { warnings.push_back(w); });
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("000000.png: a sample reads "));
  EXPECT_THAT(warnings[0], HasSubstr(", above 1023, the largest 10-bit value: the frames are not raw 10-bit DN"));
}

// A scan that stops on a bad frame leaves no cloud.ply, and no centres of the
// bad frame, of an earlier scan beside its new centres (they would be taken for
// this scan's result).
TEST(Scan, AScanStoppedByABadFrameLeavesNoEarlierCloud) {
  SyntheticRun run = MakeRun("stale_cloud", 1);
  ScanRun(run.dir, ScanOptions{});
  ASSERT_TRUE(fs::exists(run.dir / "cloud.ply"));
  std::ofstream(run.dir / "frames/000002.png") << "not a PNG";
  std::ofstream(run.dir / "centers/000002.csv") << "u,v,width,strength,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world\n";
  std::ofstream(run.dir / "manifest.jsonl", std::ios::app)
      << R"({"index":2,"shutter":{"laser_on":true},"files":{"image":"frames/000002.png"}})" << "\n";
  try {
    ScanRun(run.dir, ScanOptions{});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), (run.dir / "frames/000002.png").string());
    EXPECT_THAT(e.message(), HasSubstr("(frame 2, " + (run.dir / "manifest.jsonl").string() + ":3)"));
  }
  EXPECT_TRUE(fs::exists(run.dir / "centers/000000.csv"));
  EXPECT_FALSE(fs::exists(run.dir / "centers/000002.csv"));  // an earlier scan's (written above)
  EXPECT_FALSE(fs::exists(run.dir / "cloud.ply"));
}

}  // namespace
}  // namespace lt

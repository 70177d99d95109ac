// ScanRun without poses (a camera-frame cloud), on colour frames (the laser's
// channel weights) and the scan outputs' formats (the synthetic runs of
// scan_test_util.h).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scan_test_util.h"

namespace lt {
namespace {

using namespace scan_test;
using ::testing::HasSubstr;

TEST(Scan, CameraFrameCloudWithoutPoses) {
  SyntheticRun run = MakeRun("nopose", 1);
  // Rewrite the manifest without poses.
  std::ofstream(run.dir / "manifest.jsonl")
      << R"({"index":0,"shutter":{"laser_on":true},"files":{"image":"frames/000000.png"},"bit_depth":10})" << "\n";
  ScanSummary s = ScanRun(run.dir, ScanOptions{});
  EXPECT_FALSE(s.world_frame);
  std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_FALSE(points.empty());
  EXPECT_TRUE(points[0].p_in_cam);
  EXPECT_FALSE(points[0].p_in_world);
  std::ifstream ply(run.dir / "cloud.ply", std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(ply)), {});
  EXPECT_THAT(text, HasSubstr("camera frame"));
}

// A run of `frames` raw Bayer frames (RGGB) exposed by the sensor model
// (EMVA 1288 noise: shot, dark, quantisation): the stripe of MakeRun's laser at
// `wavelength_nm`, a pixel-integrated Gaussian of sigma 1.5 px across it whose
// peak gives `peak_e` photo-electrons in the sensor's most responsive channel.
// The sensor's quantum efficiency is the print scene's (scenes/print); its
// dark noise is 25 e- and K 0.5 DN/e- (10 bits, full well 2000 e-): a small-pixel
// sensor whose noise floor, not the stripe's shot noise, dominates near the
// default threshold.
SyntheticRun MakeSensorRun(const std::string& name, double wavelength_nm, double peak_e, int frames,
                           bool with_wavelength = true) {
  SyntheticRun run;
  run.dir = fs::temp_directory_path() / ("lt_scan_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(run.dir);
  fs::create_directories(run.dir / "frames");
  ImageSensorParams sp;
  sp.color_filter = ColorFilter::kRGGB;
  sp.qe_wavelength_m = {450e-9, 550e-9, 650e-9, 750e-9};
  sp.qe = {{{0.05, 0.1, 0.5, 0.3}, {0.1, 0.55, 0.2, 0.1}, {0.5, 0.1, 0.05, 0.08}}};
  sp.bit_depth = 10;
  sp.full_well_e = 2000;
  sp.system_gain_dn_per_e = 0.5;
  sp.dark_noise_e = 25;
  sp.black_level_dn = 16;
  SensorRig rig;
  rig.camera = run.camera;
  LaserParams lp;
  lp.wavelength_m = wavelength_nm * 1e-9;
  lp.cam_from_projector = TestLaser(1).cam_from_projector();
  rig.lasers.emplace_back(lp);
  rig.image_sensor = ImageSensor(sp);
  run.sheets.push_back(rig.lasers[0].SheetPlane(0));
  nlohmann::json rig_json = SensorRigToJson(rig);
  if (!with_wavelength) rig_json["lasers"][0].erase("wavelength_nm");  // a recorded rig that does not say
  std::ofstream(run.dir / "rig.json") << rig_json.dump(2);

  const double lambda = wavelength_nm * 1e-9;
  double best = 0;
  for (int c = 0; c < 3; ++c) best = std::max(best, rig.image_sensor.QuantumEfficiency(c, lambda));
  const double joules_per_e = kPlanck * kSpeedOfLight / lambda / best;
  const double sigma = 1.5;
  SensorExposure ex;
  ex.width = run.camera.width(), ex.height = run.camera.height();
  ex.exposure_s = 1e-4;
  MonochromaticEnergy mono;
  mono.wavelength_m = lambda;
  mono.energy_j = Image<float>(ex.width, ex.height, 1, 0.0f);
  run.rows.emplace_back();
  for (int u = 0; u < ex.width; ++u) {
    const double vc = ExactRow(run.camera, run.sheets[0], u);
    run.rows.back().push_back(vc);
    if (std::isnan(vc)) continue;
    for (int y = 0; y < ex.height; ++y) {
      const double mass = Phi((y + 0.5 - vc) / sigma) - Phi((y - 0.5 - vc) / sigma);
      mono.energy_j.At(u, y) = float(peak_e * sigma * std::sqrt(2 * M_PI) * mass * joules_per_e);
    }
  }
  ex.monochromatic.push_back(mono);
  std::ofstream manifest(run.dir / "manifest.jsonl");
  for (int f = 0; f < frames; ++f) {
    const std::string image = "frames/" + std::to_string(f) + ".png";
    WriteImage(run.dir / image, rig.image_sensor.Expose(ex, 7, uint64_t(f)));
    manifest << nlohmann::json({{"index", f}, {"shutter", {{"laser_on", true}}}, {"files", {{"image", image}}},
                                {"gt_axis", "cols"}, {"png_bit_depth", 16}, {"bit_depth", 10}})
                    .dump()
             << "\n";
  }
  return run;
}

struct CentreNoise {
  int points = 0;
  double rms = 0;  // px, from the exact rows, columns 2 .. width - 3
};

CentreNoise ScanCentreNoise(const SyntheticRun& run, const ScanOptions& o, std::vector<std::string>* warnings = nullptr) {
  const ScanSummary s = ScanRun(run.dir, o, [&](const std::string& w) {
    if (warnings) warnings->push_back(w);
  });
  CentreNoise out;
  double sum2 = 0;
  int n = 0;
  for (const ScanFrameSummary& f : s.frames) {
    for (const ScanPoint& p : ReadScanCsv(run.dir / ScanCentersName(f.index))) {
      ++out.points;
      if (p.pixel.u < 2 || p.pixel.u > run.camera.width() - 3) continue;
      const double e = p.pixel.v - run.Row(0, p.pixel.u);
      sum2 += e * e;
      ++n;
    }
  }
  out.rms = n > 0 ? std::sqrt(sum2 / n) : NAN;
  return out;
}

// A colour sensor's frames are extracted on the channels that see the laser.
// Matched weights (pipeline/channel_weights.h) against the old default, the
// mean of R, G and B, on frames whose noise floor dominates: a red (650 nm:
// QE 0.5, 0.2, 0.05) and a green laser (532 nm: 0.091, 0.469, 0.172).
TEST(Scan, ColourFramesUseTheLaserChannels) {
  ScanOptions matched;
  ScanOptions mean;
  mean.extraction.channel_weights = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  for (double wavelength_nm : {650.0, 532.0}) {
    SCOPED_TRACE(wavelength_nm);
    const std::string nm = std::to_string(int(wavelength_nm));
    // Centre noise: 8 frames of a stripe at 600 e- (300 DN) in its best channel,
    // which both find whole. Where the floor (25^2 + 1/(12 K^2) = 625 e-^2)
    // dominates, the mean's SNR is 0.82 (red) and 0.67 (green) of the matched
    // weights' (pipeline/channel_weights.h: sum(w QE) / sqrt(sum w^2 / N_c),
    // N_c the colour's pixels per 2x2 tile); the stripe's own shot noise (as
    // large as the floor at the peak in the best channel, less in the tails)
    // and the demosaicing bias bring them nearer. Measured rms 0.112 against
    // 0.130 px (red), 0.098 against 0.124 px (green); below 0.9 of the mean's
    // is asked of both.
    SyntheticRun bright = MakeSensorRun("colour_" + nm, wavelength_nm, 600, 8);
    const CentreNoise a = ScanCentreNoise(bright, matched), b = ScanCentreNoise(bright, mean);
    ASSERT_GE(a.points, 8 * 150);
    ASSERT_GE(b.points, 8 * 150);
    EXPECT_LT(a.rms, 0.9 * b.rms) << "matched " << a.rms << " px, mean " << b.rms << " px";
    // Points at the default threshold (10% of 1023 DN): a stripe at 350 e-
    // (175 DN above black) in its best channel reads 0.67 (red) or 0.82 (green)
    // of that in the matched weighted image, above the threshold, and half of
    // it in the mean, below (found only where the noise lifts it): measured 633
    // against 100 points (red), 640 against 195 (green).
    SyntheticRun faint = MakeSensorRun("faint_" + nm, wavelength_nm, 350, 4);
    const CentreNoise fa = ScanCentreNoise(faint, matched), fb = ScanCentreNoise(faint, mean);
    EXPECT_GE(fa.points, 4 * 140);
    EXPECT_LT(fb.points, fa.points / 2);
  }
}

// A rig that does not give its laser's wavelength keeps the mean of R, G and
// B, and says so.
TEST(Scan, ColourFramesWithoutWavelengthKeepTheMean) {
  SyntheticRun run = MakeSensorRun("colour_no_wavelength", 650, 900, 2, false);
  ScanOptions o;
  std::vector<std::string> warnings;
  const CentreNoise a = ScanCentreNoise(run, o, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("gives no wavelength_nm for laser 0: colour frames are extracted on the mean of R, G and B"));
  o.extraction.channel_weights = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const CentreNoise b = ScanCentreNoise(run, o);
  EXPECT_EQ(a.points, b.points);
  EXPECT_NEAR(a.rms, b.rms, 1e-6);  // the same extraction (weights 1/3 in float either way)
}

// Three-channel colour frames (a camera that demosaics itself) get the same
// matched weights; without the rig's wavelength they need --channel or --weights.
TEST(Scan, ThreeChannelColourFramesUseTheLaserChannels) {
  for (bool with_wavelength : {true, false}) {
    SyntheticRun run = MakeSensorRun(std::string("colour_rgb_") + (with_wavelength ? "1" : "0"), 650, 600, 2,
                                     with_wavelength);
    for (int f = 0; f < 2; ++f) {
      const fs::path path = run.dir / ("frames/" + std::to_string(f) + ".png");
      const Image<uint16_t> raw = std::get<Image<uint16_t>>(ReadImage(path));
      const Image<float> rgb = DemosaicBilinear(raw.View(), ColorFilter::kRGGB);
      Image<uint16_t> out(rgb.width, rgb.height, 3);
      for (size_t i = 0; i < rgb.pixels.size(); ++i) out.pixels[i] = uint16_t(std::lround(rgb.pixels[i]));
      WriteImage(path, out);
    }
    ScanOptions o;
    if (!with_wavelength) {
      try {
        ScanRun(run.dir, o);
        FAIL();
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("the image has 3 channels: choose the laser's channel"));
      }
      continue;
    }
    const ScanSummary s = ScanRun(run.dir, o);
    ASSERT_EQ(s.channel_weights.size(), 3u);
    EXPECT_GT(s.channel_weights[0], s.channel_weights[2]);
    EXPECT_NEAR(s.channel_weights[0] + s.channel_weights[1] + s.channel_weights[2], 1.0, 1e-12);
    EXPECT_GE(s.points, 2 * 150);
    o.extraction.channel_weights = s.channel_weights;  // the same, given explicitly
    EXPECT_EQ(ScanRun(run.dir, o).points, s.points);
  }
}

// The default threshold and background follow the channel weights: the
// weighted image's full scale is the frame's times the sum of the positive
// weights, its black level the black level times their sum. Weights 2,0,0 give
// the same points as 1,0,0 (a stripe below the threshold in R is found by
// neither; a brighter one at the same centres).
TEST(Scan, DefaultLevelsFollowTheWeights) {
  for (double peak_e : {150.0, 900.0}) {
    SyntheticRun run = MakeSensorRun("weights_scale_" + std::to_string(int(peak_e)), 650, peak_e, 2);
    ScanOptions one, two;
    one.extraction.channel_weights = {1, 0, 0};
    two.extraction.channel_weights = {2, 0, 0};
    const CentreNoise a = ScanCentreNoise(run, one), b = ScanCentreNoise(run, two);
    EXPECT_EQ(a.points, b.points) << peak_e;
    if (a.points > 0 && b.points > 0) {
      EXPECT_NEAR(a.rms, b.rms, 1e-6) << peak_e;
    }
    if (peak_e < 200) {
      EXPECT_LT(a.points, 2 * 50);  // 75 DN < 102.3: only where the noise lifts it
    } else {
      EXPECT_GE(a.points, 2 * 150);
    }
  }
}

TEST(ScanOutput, CsvRoundTripAndPlyLayout) {
  std::vector<ScanPoint> pts(3);
  pts[0].pixel = {10.25, 3, 4.5, 800, 0};
  pts[0].p_in_cam = Eigen::Vector3d(0.001, -0.002, 0.0812345678);
  pts[0].p_in_world = Eigen::Vector3d(1.5, 2.25, -0.125);
  pts[1].pixel = {11, 3.5, 4, 700, -1};
  pts[2].pixel = {12, 3.75, 4, 700, 1};
  pts[2].p_in_cam = Eigen::Vector3d(0, 0, 0.1);
  const std::string csv = FormatScanCsv(pts);
  EXPECT_THAT(csv, HasSubstr("\n11.00000,3.50000,4.000,700,-1,,,,,,\n"));
  EXPECT_THAT(csv, HasSubstr("\n12.00000,3.75000,4.000,700,1,0,0,0.1,,,\n"));
  fs::path p = fs::temp_directory_path() / ("lt_scan_csv_" + std::to_string(::getpid()) + ".csv");
  WriteScanCsv(p, pts);
  auto back = ReadScanCsv(p);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].pixel.u, 10.25);
  EXPECT_EQ(*back[0].p_in_cam, *pts[0].p_in_cam);
  EXPECT_EQ(*back[0].p_in_world, *pts[0].p_in_world);
  EXPECT_FALSE(back[1].p_in_cam || back[1].p_in_world);
  EXPECT_TRUE(back[2].p_in_cam && !back[2].p_in_world);
  fs::remove(p);

  PointCloud cloud;
  cloud.points.push_back({{1, 2, 3}, 7, 1, {10, 20, 30}});
  std::string ply = FormatPly(cloud);
  const std::string end = "end_header\n";
  ASSERT_NE(ply.find(end), std::string::npos);
  EXPECT_EQ(ply.size() - (ply.find(end) + end.size()), 3 * 8 + 2 * 4u);
  cloud.has_colour = true;
  ply = FormatPly(cloud);
  EXPECT_THAT(ply, HasSubstr("property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"));
  EXPECT_EQ(ply.size() - (ply.find(end) + end.size()), 3 * 8 + 2 * 4 + 3u);
  EXPECT_EQ(ply.substr(ply.size() - 3), std::string("\x0a\x14\x1e"));
  cloud.points[0].p.x() = std::nan("");
  EXPECT_THROW(FormatPly(cloud), std::invalid_argument);
}

}  // namespace
}  // namespace lt

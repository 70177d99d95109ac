// Parsing of the scene file's `sensor` section: values land where they should,
// and every invalid input is a clean InputError with the JSON pointer.
#include "sensor/rig.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "test_util.h"

namespace lt {
namespace {

using test::Doc;
using test::ErrorOf;

const char* kFull = R"({"sensor": {
  "camera": {"resolution": [1000, 700], "focal_length_mm": 8, "pixel_pitch_um": 4.8,
             "distortion": {"model": "brown_conrady", "k1": -0.1, "k2": 0.02},
             "f_number": 2.8, "focus_distance_m": 0.07},
  "image_sensor": {"color_filter": "rggb", "bit_depth": 10, "full_well_e": 9000,
                   "system_gain_dn_per_e": 0.11, "dark_noise_e": 6.5,
                   "quantum_efficiency": {"wavelength_nm": [450, 650], "r": [0.1, 0.5], "g": [0.5, 0.2], "b": [0.6, 0.05]}},
  "lasers": [{"power_mw": 5, "wavelength_nm": 650, "fan_angle_deg": 60, "divergence_deg": 0.2,
              "cam_from_projector": {"translation_m": [0.03, 0, 0], "rotation_rpy_deg": [0, -20, 0]}},
             {"power_mw": 10, "wavelength_nm": 450, "sheet_count": 5, "sheet_spacing_deg": 2,
              "cam_from_projector": {"translation_m": [-0.03, 0, 0]}}],
  "led": {"size_m": [0.01, 0.02], "radiance_w_per_m2_sr": [1, 2, 3], "cam_from_led": {"translation_m": [0, 0.02, 0]}},
  "shutter": {"frame_period_ms": 9.665, "alternating": {"bright_exposure_us": 2000, "dim_exposure_us": 100}}
}})";

TEST(Rig, ParsesFullSection) {
  auto doc = Doc(kFull);
  SensorRig rig = ParseSensorRig(doc.Root().AsObject().GetObject("sensor"));
  EXPECT_EQ(rig.camera.width(), 1000);
  EXPECT_EQ(rig.camera.height(), 700);
  EXPECT_NEAR(rig.camera.fx(), 8e-3 / 4.8e-6, 1e-9);
  EXPECT_NEAR(rig.camera.cx(), 499.5, 1e-12);
  EXPECT_NEAR(rig.camera.pixel_pitch_m(), 4.8e-6, 1e-18);
  EXPECT_EQ(rig.camera.distortion_model(), DistortionModel::kBrownConrady);
  EXPECT_FALSE(rig.camera.is_pinhole());
  EXPECT_EQ(rig.image_sensor.color_filter(), ColorFilter::kRGGB);
  EXPECT_EQ(rig.image_sensor.bit_depth(), 10);
  EXPECT_NEAR(rig.image_sensor.QuantumEfficiency(0, 550e-9), 0.3, 1e-12);
  ASSERT_EQ(rig.lasers.size(), 2u);
  EXPECT_NEAR(rig.lasers[0].power_w(), 5e-3, 1e-15);
  EXPECT_EQ(rig.lasers[1].sheet_count(), 5);
  ASSERT_TRUE(rig.led);
  EXPECT_NEAR(rig.led->area_m2(), 2e-4, 1e-15);
  EXPECT_FALSE(rig.pattern);
  EXPECT_EQ(rig.shutter.cycle_length(), 2);
  // Laser 0: rotated -20 deg about y, at x = 3 cm. Its plane contains the origin
  // of the projector and the rotated fan direction x' = R·(1,0,0).
  Plane pl = rig.lasers[0].SheetPlane(0);
  Eigen::Vector3d o = rig.lasers[0].origin_in_cam();
  EXPECT_NEAR(pl.SignedDistance(o), 0.0, 1e-15);
  EXPECT_NEAR(pl.SignedDistance(o + rig.lasers[0].cam_from_projector().linear() * Eigen::Vector3d(0.3, 0, 1)), 0.0,
              1e-15);
  auto meta = SensorRigToJson(rig);
  EXPECT_EQ(meta["lasers"][1]["sheet_planes_in_cam"].size(), 5u);
}

TEST(Rig, PixelIntrinsicsNeedPixelPitch) {
  auto doc = Doc(R"({"camera": {"resolution": [64, 48], "fx": 100, "fy": 100, "cx": 31.5, "cy": 23.5, "f_number": 4}})");
  EXPECT_EQ(ErrorOf([&] { ParseSensorRig(doc.Root().AsObject()); }),
            "scene.json: /camera: missing required key \"pixel_pitch_um\"");
}

// OpenCV's distCoeffs come in 4, 5, 8, 12 or 14 elements (calibrateCamera writes
// 5, ROS camera_info and CALIB_RATIONAL_MODEL files 8, some tools 4); only 5 were
// read ("must have 5 elements, got 4"). Terms past k3 are not modelled: zero only.
TEST(Rig, DistortionCoefficientsTakeOpenCvLengths) {
  auto camera = [](const std::string& coefficients) {
    auto doc = Doc(R"({"camera": {"resolution": [64, 48], "fx": 100, "fy": 100, "cx": 31.5, "cy": 23.5, "pixel_pitch_um": 5,
        "f_number": 4, "distortion": {"model": "brown_conrady", "coefficients": )" + coefficients + "}}}");
    return ParseSensorRig(doc.Root().AsObject()).camera;
  };
  const auto four = camera("[-0.1, 0.02, 0.001, -0.002]").params().brown_conrady;
  EXPECT_EQ(four.k1, -0.1);
  EXPECT_EQ(four.k2, 0.02);
  EXPECT_EQ(four.p1, 0.001);
  EXPECT_EQ(four.p2, -0.002);
  EXPECT_EQ(four.k3, 0.0);
  const auto eight = camera("[-0.1, 0.02, 0.001, -0.002, 0.003, 0, 0, 0]").params().brown_conrady;
  EXPECT_EQ(eight.k3, 0.003);
  EXPECT_EQ(eight.p2, -0.002);
  EXPECT_EQ(camera("[-0.1, 0.02, 0, 0, 0.003, 0, 0, 0, 0, 0, 0, 0, 0, 0]").params().brown_conrady.k3, 0.003);
  EXPECT_EQ(ErrorOf([&] { camera("[-0.1, 0.02, 0, 0, 0, 0.5, 0, 0]"); }),
            "scene.json: /camera/distortion/coefficients/5: k4 is not modelled (only k1 k2 p1 p2 k3): must be 0, got 0.5");
  EXPECT_EQ(ErrorOf([&] { camera("[-0.1, 0.02, 0, 0, 0, 0]"); }).rfind(
                "scene.json: /camera/distortion/coefficients: must have 4, 5, 8, 12 or 14 elements", 0),
            0u);
  // The fisheye model has OpenCV's four.
  auto doc = Doc(R"({"camera": {"resolution": [64, 48], "fx": 100, "fy": 100, "cx": 31.5, "cy": 23.5, "pixel_pitch_um": 5,
      "f_number": 4, "distortion": {"model": "fisheye", "coefficients": [0.1, 0, 0, 0, 0]}}})");
  EXPECT_EQ(ErrorOf([&] { ParseSensorRig(doc.Root().AsObject()); }),
            "scene.json: /camera/distortion/coefficients: must have 4 elements, got 5");
}

struct BadCase {
  std::string json;
  const char* expected;
};

TEST(Rig, InvalidParametersNameThePointer) {
  const std::string cam = R"("camera": {"resolution": [64, 48], "fx": 100, "fy": 100, "cx": 31.5, "cy": 23.5, "pixel_pitch_um": 5, "f_number": 4})";
  const std::string laser_pose = R"("cam_from_projector": {"translation_m": [0.03, 0, 0]})";
  const BadCase cases[] = {
      {R"({"sensor": {"camera": {"resolution": [64, 48], "fx": 100, "fy": 100, "cx": 31.5, "cy": 23.5, "pixel_pitch_um": 5, "f_number": 0}}})",
       "scene.json: /sensor/camera/f_number: must be > 0, got 0"},
      {R"({"sensor": {"camera": {"resolution": [64, 48], "fx": 100, "fy": 100, "cx": 31.5, "cy": 23.5, "pixel_pitch_um": 5, "f_number": 2,
          "distortion": {"model": "brown_conrady", "k1": -2.0}}}})",
       "scene.json: /sensor/camera/distortion: the distortion folds inside the image"},
      {(R"({"sensor": {)" + cam + R"(, "image_sensor": {"full_well_e": 0}}})"),
       "scene.json: /sensor/image_sensor/full_well_e: must be > 0, got 0"},
      {(R"({"sensor": {)" + cam + R"(, "image_sensor": {"bit_depth": 0}}})"),
       "scene.json: /sensor/image_sensor/bit_depth: must be in [1, 16], got 0"},
      {(R"({"sensor": {)" + cam + R"(, "image_sensor": {"bit_depth": 17}}})"),
       "scene.json: /sensor/image_sensor/bit_depth: must be in [1, 16], got 17"},
      {(R"({"sensor": {)" + cam + R"(, "lasers": [{"power_mw": 5, "wavelength_nm": 650, "sheet_count": 0, )" + laser_pose + "}]}}"),
       "scene.json: /sensor/lasers/0/sheet_count: must be >= 1, got 0"},
      {(R"({"sensor": {)" + cam + R"(, "lasers": [{"power_mw": 5, "wavelength_nm": 650, "cam_from_projector": {"rotation_quat_wxyz": [1, 0.1, 0, 0]}}]}})"),
       "scene.json: /sensor/lasers/0/cam_from_projector/rotation_quat_wxyz: rotation quaternion must have unit norm"},
      {(R"({"sensor": {)" + cam + R"(, "lasers": [{"power_mw": 5, "wavelength_nm": 650, "sheet_power": [1, 2], )" + laser_pose + "}]}}"),
       "scene.json: /sensor/lasers/0/sheet_power: must have one value per sheet (1), got 2"},
      {(R"({"sensor": {)" + cam + R"(, "lasers": [{"power_mw": 5, "wavelength_nm": 650, "typo": 1, )" + laser_pose + "}]}}"),
       "scene.json: /sensor/lasers/0/typo: unknown key \"typo\""},
      {(R"({"sensor": {)" + cam + R"(, "shutter": {"frame_period_ms": 10, "cycle": [{"exposure_us": 0}]}}})"),
       "scene.json: /sensor/shutter/cycle/0/exposure_us: must be > 0, got 0"},
      {(R"({"sensor": {)" + cam + R"(, "shutter": {"frame_period_ms": 10, "sync_offset_us": 6000, "cycle": [{"exposure_us": 10}]}}})"),
       "scene.json: /sensor/shutter/sync_offset_us: |sync_offset| + 5·sync_jitter must be below half the frame period"},
      {(R"({"sensor": {)" + cam + R"(, "extra": {}}})"), "scene.json: /sensor/extra: unknown key \"extra\""},
  };
  for (const auto& c : cases) {
    auto doc = Doc(c.json);
    std::string msg = ErrorOf([&] { ParseSensorRig(doc.Root().AsObject().GetObject("sensor")); });
    EXPECT_EQ(msg.rfind(c.expected, 0), 0u) << "got: " << msg << "\nexpected prefix: " << c.expected;
  }
}

// A rig holds at most kMaxRigEmitters lasers and pattern projectors and
// kMaxRigSheets sheets (the renderer's film channels): more is refused at the
// laser or projector that goes over, before anything is rendered.
TEST(Rig, EmitterAndSheetLimitsNameThePointer) {
  const std::string cam = R"("camera": {"resolution": [64, 48], "focal_length_mm": 4, "pixel_pitch_um": 4.8, "f_number": 4})";
  auto laser = [](int sheets) {
    std::string l = R"({"power_mw": 1, "wavelength_nm": 650, "fan_angle_deg": 30, "cam_from_projector": {"translation_m": [0, 0.03, 0]})";
    if (sheets > 1) l += R"(, "sheet_count": )" + std::to_string(sheets) + R"(, "sheet_spacing_deg": 1)";
    return l + "}";
  };
  auto rig_with = [&](const std::vector<int>& sheets, bool pattern) {
    std::string j = R"({"sensor": {)" + cam + R"(, "lasers": [)";
    for (size_t i = 0; i < sheets.size(); ++i) {
      if (i) j += ",";
      j += laser(sheets[i]);
    }
    j += "]";
    if (pattern) j += R"(, "pattern_projector": {"image": "p.png", "fov_deg": 30, "power_mw": 1, "wavelength_nm": 650})";
    return j + "}}";
  };
  auto error_of = [](const std::string& json) {
    auto doc = Doc(json);
    return ErrorOf([&] { ParseSensorRig(doc.Root().AsObject().GetObject("sensor")); });
  };
  auto full = Doc(rig_with({60, 4}, false));
  EXPECT_EQ(ParseSensorRig(full.Root().AsObject().GetObject("sensor")).lasers.size(), 2u);
  EXPECT_EQ(error_of(rig_with({60, 5}, false)).rfind("scene.json: /sensor/lasers/1: the lasers up to this one have 65 sheets", 0), 0u);
  EXPECT_EQ(error_of(rig_with({65}, false)), "scene.json: /sensor/lasers/0/sheet_count: must be <= 64, got 65");
  EXPECT_EQ(error_of(rig_with(std::vector<int>(9, 1), false))
                .rfind("scene.json: /sensor/lasers/8: a rig holds at most 8 lasers and pattern projectors", 0),
            0u);
  EXPECT_EQ(error_of(rig_with({64}, true)).rfind("scene.json: /sensor/pattern_projector: the rig is full", 0), 0u);
  EXPECT_EQ(error_of(rig_with(std::vector<int>(8, 1), true)).rfind("scene.json: /sensor/pattern_projector: the rig is full", 0), 0u);
  EXPECT_EQ(error_of(rig_with({1}, true)).rfind("scene.json: /sensor/pattern_projector/image: pattern image not found", 0), 0u);
}

// The example in docs/scene-format.md parses and means what the text says.
TEST(Rig, DocumentedExampleParses) {
  std::ifstream in(std::string(LT_SOURCE_DIR) + "/docs/scene-format.md");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string md = ss.str();
  size_t section = md.find("## sensor");
  ASSERT_NE(section, std::string::npos);
  size_t start = md.find("```json\n", section);
  ASSERT_NE(start, std::string::npos);
  start += 8;
  size_t end = md.find("```", start);
  std::string text = "{";
  text.append(md, start, end - start);
  text += "}";
  auto doc = Doc(text);
  SensorRig rig = ParseSensorRig(doc.Root().AsObject().GetObject("sensor"));
  EXPECT_EQ(rig.camera.width(), 1000);
  ASSERT_EQ(rig.lasers.size(), 1u);
  // The sheet passes the camera's centre at a baseline, as a scanner's must
  // (a sheet through the centre shows every point on one line: nothing to triangulate).
  EXPECT_GT(std::abs(rig.lasers[0].SheetPlane(0).SignedDistance(Eigen::Vector3d::Zero())), 0.02);
  EXPECT_TRUE(rig.led.has_value());
  EXPECT_EQ(rig.shutter.Frame(0).label, "bright");
  EXPECT_TRUE(rig.shutter.Frame(1).laser_on);
}

TEST(Rig, DefaultsWhenOptionalPartsAreAbsent) {
  auto doc = Doc(R"({"camera": {"resolution": [64, 48], "focal_length_mm": 4, "pixel_pitch_um": 3, "f_number": 2}})");
  SensorRig rig = ParseSensorRig(doc.Root().AsObject());
  EXPECT_TRUE(rig.camera.is_pinhole());
  EXPECT_NEAR(rig.camera.cx(), 31.5, 1e-12);
  EXPECT_EQ(rig.image_sensor.color_filter(), ColorFilter::kMono);
  EXPECT_EQ(rig.image_sensor.bit_depth(), 12);
  EXPECT_TRUE(rig.lasers.empty());
  EXPECT_FALSE(rig.led);
  EXPECT_TRUE(rig.shutter.Frame(0).laser_on);
}

TEST(Rig, BayerNeedsPerChannelQuantumEfficiency) {
  auto doc = Doc(R"({"camera": {"resolution": [64, 48], "focal_length_mm": 4, "pixel_pitch_um": 3, "f_number": 2},
                    "image_sensor": {"color_filter": "rggb", "quantum_efficiency": 0.5}})");
  EXPECT_EQ(ErrorOf([&] { ParseSensorRig(doc.Root().AsObject()); })
                .rfind("scene.json: /image_sensor/quantum_efficiency: a Bayer sensor needs per-channel tables", 0),
            0u);
  auto doc2 = Doc(R"({"camera": {"resolution": [64, 48], "focal_length_mm": 4, "pixel_pitch_um": 3, "f_number": 2,
                                "distortion": {"model": "none", "k1": 0.1}}})");
  EXPECT_EQ(ErrorOf([&] { ParseSensorRig(doc2.Root().AsObject()); }).rfind("scene.json: /camera/distortion/k1: unknown key", 0), 0u);
}

}  // namespace
}  // namespace lt

// Files of several cameras through ReadCalibrationFile with --calib-camera
// (CalibrationFileOptions::camera): a Kalibr stereo camchain, a VINS-Fusion
// config naming its cameras' camodocal files, a COLMAP cameras.txt of two.
// The chosen camera's values read exactly; without the option, or with a name
// the file does not hold, an error at file:line naming every camera.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "pipeline/calibration_file.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using Err = std::pair<std::string, std::string>;

fs::path Dir() { return fs::temp_directory_path() / ("lt_calib_cameras_test_" + std::to_string(::getpid())); }

fs::path TempFile(const std::string& name, const std::string& text) {
  fs::create_directories(Dir());
  fs::path p = Dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

CalibrationFileOptions Camera(const std::string& name) {
  CalibrationFileOptions o;
  o.camera = name;
  return o;
}

// The error for `text` read with `o`: "where" after the file name, and the message.
Err ErrorOf(const std::string& name, const std::string& text, const CalibrationFileOptions& o = {}) {
  const fs::path p = TempFile(name, text);
  try {
    ReadCalibrationFile(p, o);
  } catch (const InputError& e) {
    return {e.where().substr(std::min(e.where().size(), p.string().size())), e.message()};
  }
  return {"no error", ""};
}

// Kalibr's stereo camchain: cam1 with its T_cn_cnm1 (cam1_from_cam0).
const char* kKalibrStereo = R"(cam0:
  T_cam_imu:
  - [0.0148, -0.9998, 0.0041, -0.0216]
  - [0.9995, 0.0149, 0.0257, -0.0646]
  - [-0.0257, 0.0037, 0.9996, 0.0098]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [-0.2834, 0.0739, 0.00019, 1.76e-05]
  distortion_model: radtan
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  resolution: [752, 480]
cam1:
  T_cam_imu:
  - [0.0125, -0.9999, 0.0040, 0.0895]
  - [0.9998, 0.0125, -0.0130, -0.0644]
  - [0.0130, 0.0038, 0.9999, 0.0100]
  - [0.0, 0.0, 0.0, 1.0]
  T_cn_cnm1:
  - [0.99999, 0.00231, 0.00037, -0.11007]
  - [-0.00231, 0.99990, 0.01408, 0.00039]
  - [-0.00034, -0.01408, 0.99990, -0.00085]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [-0.28368, 0.07451, -0.00010, -3.5555e-05]
  distortion_model: radtan
  intrinsics: [457.587, 456.134, 379.999, 255.238]
  resolution: [752, 480]
)";

TEST(CalibrationFileCameras, KalibrCameraChosenByItsKey) {
  const CalibrationFile c1 = ReadCalibrationFile(TempFile("camchain.yaml", kKalibrStereo), Camera("cam1"));
  ASSERT_TRUE(c1.camera);
  EXPECT_EQ(std::vector<double>({c1.camera->fx, c1.camera->fy, c1.camera->cx, c1.camera->cy, c1.camera->brown_conrady.k1,
                                 c1.camera->brown_conrady.p2}),
            std::vector<double>({457.587, 456.134, 379.999, 255.238, -0.28368, -3.5555e-05}));
  // Its extrinsics are cam1's own, and not read (nothing of cam0's is applied to it).
  EXPECT_EQ(c1.ignored_keys, (std::vector<std::string>{"cam1.T_cam_imu", "cam1.T_cn_cnm1", "cam0"}));
  EXPECT_FALSE(c1.tool_from_cam);
  const CalibrationFile c0 = ReadCalibrationFile(TempFile("camchain.yaml", kKalibrStereo), Camera("cam0"));
  ASSERT_TRUE(c0.camera);
  EXPECT_EQ(c0.camera->fx, 458.654);
  EXPECT_EQ(ErrorOf("camchain.yaml", kKalibrStereo),
            (Err{":12", "a Kalibr camera chain of 2 cameras: give --calib-camera with the scanner camera's: 'cam0', "
                        "'cam1'"}));
  EXPECT_EQ(ErrorOf("camchain.yaml", kKalibrStereo, Camera("cam2")),
            (Err{":1", "no camera 'cam2' in a Kalibr camera chain: its cameras are 'cam0', 'cam1'"}));
}

const char* kCam0 = "%YAML:1.0\n---\nmodel_type: PINHOLE\ncamera_name: camera\nimage_width: 752\nimage_height: 480\n"
                    "distortion_parameters:\n   k1: -2.917e-01\n   k2: 8.228e-02\n   p1: 5.333e-05\n   p2: -1.578e-04\n"
                    "projection_parameters:\n   fx: 4.616e+02\n   fy: 4.603e+02\n   cx: 3.630e+02\n   cy: 2.484e+02\n";
const char* kCam1 = "%YAML:1.0\n---\nmodel_type: PINHOLE\ncamera_name: camera\nimage_width: 752\nimage_height: 480\n"
                    "distortion_parameters:\n   k1: -2.9545645106987750e-01\n   k2: 8.6623215640186171e-02\n"
                    "   p1: 2.0132892276082517e-06\n   p2: 1.3924531371276508e-05\nprojection_parameters:\n"
                    "   fx: 4.6115862106007575e+02\n   fy: 4.5975286598073296e+02\n   cx: 3.6265929181685937e+02\n"
                    "   cy: 2.4852105668448124e+02\n";

// VINS-Fusion's euroc_stereo_imu_config.yaml, abridged: the cameras in files beside it.
std::string VinsConfig(int cameras, const std::string& cam1_file = "cam1_pinhole.yaml") {
  return "%YAML:1.0\n\n#common parameters\nimu: 1\nnum_of_cam: " + std::to_string(cameras) +
         "\n\nimu_topic: \"/imu0\"\nimage0_topic: \"/cam0/image_raw\"\nimage1_topic: \"/cam1/image_raw\"\n\n"
         "cam0_calib: \"cam0_pinhole.yaml\"\ncam1_calib: \"" + cam1_file + "\"\nimage_width: 752\nimage_height: 480\n"
         "body_T_cam0: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n   data: [0.0148, -0.9998, 0.0041, -0.0216,\n"
         "      0.9995, 0.0149, 0.0257, -0.0646, -0.0257, 0.0037, 0.9996, 0.0098, 0, 0, 0, 1]\n"
         "body_T_cam1: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n   data: [0.0125, -0.9999, 0.0040, 0.0895,\n"
         "      0.9998, 0.0125, -0.0130, -0.0644, 0.0130, 0.0038, 0.9999, 0.0100, 0, 0, 0, 1]\n";
}

TEST(CalibrationFileCameras, VinsFusionConfigReadsTheChosenCameraFile) {
  TempFile("cam0_pinhole.yaml", kCam0);
  TempFile("cam1_pinhole.yaml", kCam1);
  const CalibrationFile c1 = ReadCalibrationFile(TempFile("vins.yaml", VinsConfig(2)), Camera("cam1"));
  ASSERT_TRUE(c1.camera);
  EXPECT_EQ(std::vector<double>({double(c1.camera->width), c1.camera->fx, c1.camera->fy, c1.camera->cx, c1.camera->cy,
                                 c1.camera->brown_conrady.k1, c1.camera->brown_conrady.p2}),
            std::vector<double>({752, 4.6115862106007575e+02, 4.5975286598073296e+02, 3.6265929181685937e+02,
                                 2.4852105668448124e+02, -2.9545645106987750e-01, 1.3924531371276508e-05}));
  EXPECT_THAT(c1.ignored_keys, ::testing::IsSupersetOf({"camera_name", "body_T_cam1", "cam0_calib"}));
  // Several cameras without the option; one camera (num_of_cam 1) reads cam0's file.
  EXPECT_EQ(ErrorOf("vins.yaml", VinsConfig(2)),
            (Err{":12", "a VINS-Fusion config of 2 cameras: give --calib-camera with the scanner camera's: 'cam0', "
                        "'cam1'"}));
  const CalibrationFile c0 = ReadCalibrationFile(TempFile("vins.yaml", VinsConfig(1)));
  ASSERT_TRUE(c0.camera);
  EXPECT_EQ(c0.camera->fx, 4.616e+02);
  EXPECT_EQ(ErrorOf("vins.yaml", VinsConfig(1), Camera("cam1")),
            (Err{":11", "no camera 'cam1' in a VINS-Fusion config: its camera is 'cam0' (drop --calib-camera to read "
                        "it)"}));
  const Err missing = ErrorOf("vins.yaml", VinsConfig(2, "cam1_mei.yaml"), Camera("cam1"));
  EXPECT_EQ(missing.first, ":12");
  EXPECT_THAT(missing.second, ::testing::StartsWith("cam1_calib 'cam1_mei.yaml': no such file (VINS-Fusion reads it "
                                                    "beside the config: "));
  // An error in the camera's file names that file and line.
  TempFile("cam1_bad.yaml", std::string(kCam1).replace(std::string(kCam1).find("PINHOLE"), 7, "MEI"));
  try {
    ReadCalibrationFile(TempFile("vins.yaml", VinsConfig(2, "cam1_bad.yaml")), Camera("cam1"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), (Dir() / "cam1_bad.yaml").string() + ":3");
  }
}

TEST(CalibrationFileCameras, ColmapCameraChosenByItsId) {
  const std::string text = "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, "
                           "PARAMS[]\n1 PINHOLE 640 480 500.5 501 320.25 240.75\n2 OPENCV 800 600 610.5 611 400.25 "
                           "300.75 -0.2 0.05 0.001 -0.002\n";
  const CalibrationFile c = ReadCalibrationFile(TempFile("cameras.txt", text), Camera("2"));
  ASSERT_TRUE(c.camera);
  EXPECT_EQ(std::vector<double>({double(c.camera->width), c.camera->fx, c.camera->fy, c.camera->cx, c.camera->cy,
                                 c.camera->brown_conrady.p2}),
            std::vector<double>({800, 610.5, 611, 399.75, 300.25, -0.002}));
  EXPECT_EQ(ErrorOf("cameras.txt", text),
            (Err{":4", "a COLMAP cameras.txt of 2 cameras: give --calib-camera with the scanner camera's: '1', '2'"}));
  EXPECT_EQ(ErrorOf("cameras.txt", text, Camera("3")),
            (Err{":3", "no camera '3' in a COLMAP cameras.txt: its cameras are '1', '2'"}));
}

TEST(CalibrationFileCameras, FileOfOneCameraMustBeTheOneNamed) {
  // A camodocal file names its camera (camera_name); an OpenCV file names none.
  EXPECT_EQ(ErrorOf("cam1.yaml", kCam1, Camera("cam1")),
            (Err{":4", "no camera 'cam1' in camodocal's camera file (its camera_name): its camera is 'camera' (drop "
                       "--calib-camera to read it)"}));
  EXPECT_TRUE(ReadCalibrationFile(TempFile("cam1.yaml", kCam1), Camera("camera")).camera);
  const std::string opencv = "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ncamera_matrix: !!opencv-matrix\n"
                             "   rows: 3\n   cols: 3\n   dt: d\n   data: [500, 0, 320, 0, 500, 240, 0, 0, 1]\n";
  const Err e = ErrorOf("calib.yaml", opencv, Camera("cam1"));
  EXPECT_EQ(e.first, "");
  EXPECT_THAT(e.second, ::testing::StartsWith("--calib-camera 'cam1': an OpenCV FileStorage file holds one camera and "
                                              "names none (drop --calib-camera to read it)"));
  std::string one = kKalibrStereo;
  one.resize(one.find("cam1:"));
  EXPECT_EQ(ReadCalibrationFile(TempFile("cam0.yaml", one), Camera("cam0")).camera->fx, 458.654);
}

}  // namespace
}  // namespace lt

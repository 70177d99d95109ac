// Camera files of other tools through ReadCalibrationFile (the `--calib`
// reader): tiny equivalents of real files (docs/pipeline.md, "Real files
// checked"): OpenCV's calibration sample with its 2-channel image points, ROS
// camera_info (camera_calibration's ost.yaml and a CameraInfo message as
// rostopic echo prints it), Kalibr camchains and camodocal (VINS) cameras; the
// same camera in each form reads the same; what cannot be honoured is an error
// at file:line, a stereo rectification a warning.
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
using ::testing::HasSubstr;

fs::path TempFile(const std::string& name, const std::string& text) {
  fs::path dir = fs::temp_directory_path() / ("lt_calib_formats_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::path p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// The error ReadCalibrationFile throws for `text`: "where" after the file name and the message.
std::pair<std::string, std::string> ErrorOf(const std::string& name, const std::string& text) {
  const fs::path p = TempFile(name, text);
  try {
    ReadCalibrationFile(p);
  } catch (const InputError& e) {
    return {e.where().substr(std::min(e.where().size(), p.string().size())), e.message()};
  }
  return {"no error", ""};
}

// OpenCV's camera calibration sample writes its image points as a 2-channel
// matrix (dt "2f"), in YAML and XML. (Before: refused, "dt must be one channel".)
TEST(CalibrationFileFormats, OpenCvSampleWithTwoChannelImagePoints) {
  const std::string yaml = R"(%YAML:1.0
calibration_time: "Fri 02 Dec 2016 02:32:00 PM PST"
image_width: 1384
image_height: 1032
flags: 6158
fisheye_model: 0
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 3.2e+02, 0., 6.915e+02, 0., 3.2e+02, 5.155e+02, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 5
   cols: 1
   dt: d
   data: [ -0.1, 0.01, 0., 0., 0. ]
image_points: !!opencv-matrix
   rows: 1
   cols: 2
   dt: "2f"
   data: [ 7.46671936e+02, 5.49919800e+02, 7.17155762e+02,
       5.51332886e+02 ]
)";
  CalibrationFile c = ReadCalibrationFile(TempFile("sample.yml", yaml));
  ASSERT_TRUE(c.camera);
  EXPECT_EQ(c.camera->cx, 691.5);
  EXPECT_EQ(c.camera->brown_conrady.k1, -0.1);
  EXPECT_THAT(c.ignored_keys, ::testing::Contains("image_points"));
  const std::string xml = R"(<?xml version="1.0"?>
<opencv_storage>
<image_width>4080</image_width>
<image_height>3072</image_height>
<camera_matrix type_id="opencv-matrix">
  <rows>3</rows><cols>3</cols><dt>d</dt>
  <data>1.5446672816644511e+03 0. 2.0395e+03 0. 1.5446672816644511e+03 1.5355e+03 0. 0. 1.</data></camera_matrix>
<image_points type_id="opencv-matrix">
  <rows>1</rows><cols>2</cols><dt>"2f"</dt>
  <data>8.56926392e+02 2.37463525e+03 9.55771057e+02 2.20159570e+03</data></image_points>
<grid_points>
  0. 0. 0. 50. 0. 0.</grid_points>
</opencv_storage>
)";
  CalibrationFile x = ReadCalibrationFile(TempFile("sample.xml", xml));
  ASSERT_TRUE(x.camera);
  EXPECT_EQ(x.camera->cy, 1535.5);
  EXPECT_EQ(x.camera->distortion, DistortionModel::kNone);
  // A 2-channel matrix with the values of a 1-channel one is still an error at its data line.
  EXPECT_EQ(ErrorOf("short.yml", "%YAML:1.0\nimage_points: !!opencv-matrix\n   rows: 1\n   cols: 2\n   dt: 2f\n"
                                 "   data: [ 1., 2. ]\n"),
            (std::pair<std::string, std::string>{":6", "matrix 'image_points' is 1x2 of 2 channels and needs 4 values, got 2"}));
}

// ROS camera_info as camera_calibration writes it (ost.yaml: no %YAML
// header, nested maps, data over several lines). (Before: refused, "the first
// line must be %YAML:1.0".)
TEST(CalibrationFileFormats, RosCameraInfo) {
  const std::string head = R"(image_width: 640
image_height: 480
camera_name: narrow_stereo
camera_matrix:
  rows: 3
  cols: 3
  data: [534.44522,   0.     , 311.47317,
           0.     , 536.00924, 268.39905,
           0.     ,   0.     ,   1.     ]
)";
  const std::string tail = R"(rectification_matrix:
  rows: 3
  cols: 3
  data: [1., 0., 0.,
         0., 1., 0.,
         0., 0., 1.]
projection_matrix:
  rows: 3
  cols: 4
  data: [538.7533, 0., 311.93167, 0., 0., 542.85706, 268.44811, 0., 0., 0., 1., 0.]
)";
  const std::string plumb_bob =
      "distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n"
      "  data: [0.131136, -0.294726, 0.001356, 0.002405, 0.000000]\n";
  CalibrationFile c = ReadCalibrationFile(TempFile("ost.yaml", head + plumb_bob + tail));
  ASSERT_TRUE(c.camera);
  EXPECT_EQ(c.camera->width, 640);
  EXPECT_EQ(c.camera->fx, 534.44522);
  EXPECT_EQ(c.camera->fy, 536.00924);
  EXPECT_EQ(c.camera->cx, 311.47317);
  EXPECT_EQ(c.camera->cy, 268.39905);
  EXPECT_EQ(c.camera->distortion, DistortionModel::kBrownConrady);
  EXPECT_EQ(c.camera->brown_conrady.k2, -0.294726);
  EXPECT_EQ(c.camera->brown_conrady.p2, 0.002405);
  EXPECT_EQ(c.ignored_keys, (std::vector<std::string>{"camera_name", "rectification_matrix", "projection_matrix"}));
  EXPECT_TRUE(c.warnings.empty());
  EXPECT_TRUE(c.laser_planes.empty());

  // rational_polynomial: 8 values (or 5); k4..k6 must be 0. Data as a block sequence.
  CalibrationFile r = ReadCalibrationFile(TempFile(
      "rational.yaml", head + "distortion_model: rational_polynomial\ndistortion_coefficients:\n  rows: 1\n  cols: 8\n"
                              "  data:\n  - -0.25\n  - 0.07\n  - 0.0\n  - 0.0\n  - 0.01\n  - 0.0\n  - 0.0\n  - 0.0\n"));
  ASSERT_TRUE(r.camera);
  EXPECT_EQ(r.camera->brown_conrady.k1, -0.25);
  EXPECT_EQ(r.camera->brown_conrady.k3, 0.01);
  // equidistant: OpenCV's fisheye k1..k4.
  CalibrationFile f = ReadCalibrationFile(TempFile(
      "equidistant.yaml",
      head + "distortion_model: equidistant\ndistortion_coefficients:\n  rows: 1\n  cols: 4\n  data: [0.1, -0.02, 0.003, -0.0004]\n"));
  ASSERT_TRUE(f.camera);
  EXPECT_EQ(f.camera->distortion, DistortionModel::kFisheye);
  EXPECT_EQ(f.camera->fisheye.k4, -0.0004);
  // Without distortion_model (older files): plumb_bob, as ROS takes it.
  CalibrationFile o = ReadCalibrationFile(TempFile(
      "old.yaml", head + "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [-0.2, 0, 0, 0, 0]\n"));
  ASSERT_TRUE(o.camera);
  EXPECT_EQ(o.camera->brown_conrady.k1, -0.2);
  // A stereo pair's rectification: read, with a warning naming its line.
  const std::string rotated = "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [0.9998, -0.02, 0, 0.02, 0.9998, 0, 0, 0, 1]\n";
  CalibrationFile s = ReadCalibrationFile(TempFile("left.yaml", head + plumb_bob + rotated));
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_THAT(s.warnings[0], HasSubstr("left.yaml:15: rectification_matrix is not the identity"));

  // What cannot be honoured: errors at the line.
  using Err = std::pair<std::string, std::string>;
  EXPECT_EQ(ErrorOf("k4.yaml", head + "distortion_model: rational_polynomial\ndistortion_coefficients:\n  rows: 1\n"
                                      "  cols: 8\n  data: [-0.25, 0.07, 0, 0, 0.01, 0.5, 0, 0]\n"),
            (Err{":11", "distortion_coefficients element 6: k4 is not modelled (only k1 k2 p1 p2 k3): must be 0, got 0.5"}));
  EXPECT_EQ(ErrorOf("model.yaml", head + "distortion_model: double_sphere\n"),
            (Err{":10", "distortion_model must be brown_conrady (plumb_bob, rational_polynomial, radtan) or fisheye "
                        "(equidistant), got 'double_sphere'"}));
  EXPECT_EQ(ErrorOf("skew.yaml", "image_width: 640\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
                                 "  data: [500, 2, 320, 0, 500, 240, 0, 0, 1]\n"),
            (Err{":3", "camera_matrix: skew (row 0, column 1) is not supported, got 2"}));
  EXPECT_EQ(ErrorOf("count.yaml", "image_width: 640\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
                                  "  data: [500, 0, 320, 0, 500, 240, 0, 0]\n"),
            (Err{":3", "camera_matrix is 3x3 and needs 9 values, got 8"}));
  const Err open = ErrorOf("open.yaml", "image_width: 640\ncamera_matrix:\n  rows: 3\n  data: [500, 0, 320,\n");
  EXPECT_EQ(open.first, ":4");
  EXPECT_THAT(open.second, HasSubstr("missing value in '[500, 0, 320,'"));
  EXPECT_EQ(ErrorOf("noheight.yaml", "image_width: 640\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
                                     "  data: [500, 0, 320, 0, 500, 240, 0, 0, 1]\n"),
            (Err{":1", "a ROS camera_info file needs 'image_height'"}));
}

// A CameraInfo message saved from `rostopic echo` (K, D, ..., ending in ---)
// or `ros2 topic echo` (k, d as block sequences).
TEST(CalibrationFileFormats, RosCameraInfoMessage) {
  const std::string ros1 = R"(header:
  seq: 0
  stamp:
    secs: 0
    nsecs:         0
  frame_id: short_camera
height: 480
width: 640
distortion_model: "plumb_bob"
D: [-0.3, 0.1, 0.001, -0.002, 0.0]
K: [500.0, 0.0, 319.5, 0.0, 501.0, 239.5, 0.0, 0.0, 1.0]
R: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
P: [480.0, 0.0, 319.5, 0.0, 0.0, 481.0, 239.5, 0.0, 0.0, 0.0, 1.0, 0.0]
binning_x: 0
binning_y: 0
roi:
  x_offset: 0
  y_offset: 0
  height: 0
  width: 0
  do_rectify: False
---
)";
  CalibrationFile a = ReadCalibrationFile(TempFile("echo.yaml", ros1));
  ASSERT_TRUE(a.camera);
  EXPECT_EQ(a.camera->fy, 501);
  EXPECT_EQ(a.camera->brown_conrady.p2, -0.002);
  const std::string ros2 =
      "header:\n  stamp:\n    sec: 1662013622\n    nanosec: 672922214\n  frame_id: default_cam\nheight: 1080\n"
      "width: 1920\ndistortion_model: plumb_bob\nd:\n- 0.169978\n- -0.297303\n- -0.002944\n- -0.004961\n- 0.0\n"
      "k:\n- 1726.597634\n- 0.0\n- 904.979671\n- 0.0\n- 1737.359551\n- 529.123375\n- 0.0\n- 0.0\n- 1.0\n"
      "binning_x: 0\nbinning_y: 0\nroi:\n  x_offset: 0\n  y_offset: 0\n  height: 0\n  width: 0\n  do_rectify: false\n";
  CalibrationFile b = ReadCalibrationFile(TempFile("echo2.yaml", ros2));
  ASSERT_TRUE(b.camera);
  EXPECT_EQ(b.camera->width, 1920);
  EXPECT_EQ(b.camera->cx, 904.979671);
  EXPECT_EQ(b.camera->brown_conrady.k2, -0.297303);
  // Binning: K is the full sensor's.
  std::string binned = ros1;
  binned.replace(binned.find("binning_x: 0"), 12, "binning_x: 2");
  EXPECT_EQ(ErrorOf("binned.yaml", binned).first, ":14");
  // An OpenCV file with keys of the same names is not taken for a message.
  EXPECT_THAT(ErrorOf("opencv_k.yml", "%YAML:1.0\nwidth: 640\nheight: 480\nK: !!opencv-matrix\n   rows: 3\n   cols: 3\n"
                                      "   dt: d\n   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n")
                  .second,
              HasSubstr("holds nothing lasertwin reads"));
}

// Kalibr's camchain (camchain-imucam) with one camera; radtan and
// equidistant; several cameras refused. (Before: refused, "%YAML:1.0", or with
// OpenVINS' %YAML:1.0 header every key ignored and the run's true camera used.)
TEST(CalibrationFileFormats, KalibrCamchain) {
  const std::string cam0 = R"(cam0:
  T_cam_imu:
  - [-0.99951, 0.02187, -0.02200, 0.04246]
  - [0.02534, 0.98475, -0.17207, 0.00051]
  - [0.01790, -0.17254, -0.98483, -0.01597]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: []
  camera_model: pinhole
  distortion_coeffs: [-0.027396339719770575, 0.09512490805715525, -0.11279506361711115,
    0.05123810380038282]
  distortion_model: equidistant
  intrinsics: [274.51623038381354, 275.33528152592356, 313.61364519480173, 251.55631360961928]
  resolution: [640, 480]
  rostopic: /cam0/image_raw
  timeshift_cam_imu: -0.005869528576852833
)";
  CalibrationFile k = ReadCalibrationFile(TempFile("camchain.yaml", cam0));
  ASSERT_TRUE(k.camera);
  EXPECT_EQ(k.camera->width, 640);
  EXPECT_EQ(k.camera->height, 480);
  EXPECT_EQ(k.camera->fx, 274.51623038381354);
  EXPECT_EQ(k.camera->fy, 275.33528152592356);
  EXPECT_EQ(k.camera->cx, 313.61364519480173);
  EXPECT_EQ(k.camera->cy, 251.55631360961928);
  EXPECT_EQ(k.camera->distortion, DistortionModel::kFisheye);
  EXPECT_EQ(k.camera->fisheye.k4, 0.05123810380038282);
  EXPECT_EQ(k.ignored_keys,
            (std::vector<std::string>{"cam0.T_cam_imu", "cam0.cam_overlaps", "cam0.rostopic", "cam0.timeshift_cam_imu"}));
  // radtan: k1 k2 r1 r2 (OpenCV's k1 k2 p1 p2); OpenVINS writes a %YAML:1.0 header.
  const std::string radtan = "%YAML:1.0\ncam0:\n  camera_model: pinhole\n  distortion_model: radtan\n"
                             "  distortion_coeffs: [-0.28, 0.07, 0.0002, -0.0001]\n  intrinsics: [458.6, 457.3, 367.2, 248.4]\n"
                             "  resolution: [752, 480]\n";
  CalibrationFile r = ReadCalibrationFile(TempFile("radtan.yaml", radtan));
  ASSERT_TRUE(r.camera);
  EXPECT_EQ(r.camera->distortion, DistortionModel::kBrownConrady);
  EXPECT_EQ(r.camera->brown_conrady.p1, 0.0002);
  EXPECT_EQ(r.camera->brown_conrady.k3, 0);

  using Err = std::pair<std::string, std::string>;
  const std::string cam1 = "cam1:\n  T_cn_cnm1:\n  - [1, 0, 0, -0.11]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n"
                           "  camera_model: pinhole\n  intrinsics: [461.5, 460.1, 356.4, 231.2]\n  resolution: [752, 480]\n";
  EXPECT_EQ(ErrorOf("stereo.yaml", cam0 + cam1),
            (Err{":16", "a Kalibr camera chain of 2 cameras: give --calib-camera with the scanner camera's: 'cam0', "
                        "'cam1'"}));
  std::string omni = radtan;
  omni.replace(omni.find("pinhole"), 7, "omni");
  EXPECT_EQ(ErrorOf("omni.yaml", omni).first, ":3");
  EXPECT_EQ(ErrorOf("fov.yaml", "cam0:\n  intrinsics: [458.6, 457.3, 367.2, 248.4]\n  resolution: [752, 480]\n"
                                "  distortion_model: fov\n  distortion_coeffs: [0.9]\n")
                .first,
            ":4");
}

// camodocal's camera (VINS-Mono's config: the camera among the estimator's
// keys). (Before: refused, "missing camera_matrix".)
TEST(CalibrationFileFormats, CamodocalCamera) {
  const std::string pinhole = R"(%YAML:1.0

#common parameters
imu_topic: "/imu0"
output_path: "/home/user/output/"

#camera calibration 
model_type: PINHOLE
camera_name: camera
image_width: 752
image_height: 480
distortion_parameters:
   k1: -2.9839715720358556e-01
   k2: 9.2224519780237782e-02
   p1: -1.1990340691497372e-04
   p2: -7.4597868882045419e-05
projection_parameters:
   fx: 4.6894439430045497e+02
   fy: 4.6967991177317680e+02
   cx: 3.5308385782266549e+02
   cy: 2.2974410036895023e+02
extrinsicRotation: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [0.0148655429818, -0.999880929698, 0.00414029679422,
           0.999557249008, 0.0149672133247, 0.025715529948, 
           -0.0257744366974, 0.00375618835797, 0.999660727178]
max_cnt: 150            # max feature number in feature tracking
)";
  CalibrationFile p = ReadCalibrationFile(TempFile("euroc_config.yaml", pinhole));
  ASSERT_TRUE(p.camera);
  EXPECT_EQ(p.camera->width, 752);
  EXPECT_EQ(p.camera->fx, 4.6894439430045497e+02);
  EXPECT_EQ(p.camera->cy, 2.2974410036895023e+02);
  EXPECT_EQ(p.camera->brown_conrady.k1, -2.9839715720358556e-01);
  EXPECT_EQ(p.camera->brown_conrady.p2, -7.4597868882045419e-05);
  EXPECT_EQ(p.ignored_keys,
            (std::vector<std::string>{"imu_topic", "output_path", "camera_name", "extrinsicRotation", "max_cnt"}));
  const std::string kb = "%YAML:1.0\n---\nmodel_type: KANNALA_BRANDT\ncamera_name: cam0\nimage_width: 640\n"
                         "image_height: 512\nprojection_parameters:\n   k2: -0.061\n   k3: -0.0038\n   k4: 0.027\n"
                         "   k5: -0.030\n   mu: 413.3\n   mv: 413.7\n   u0: 305.9\n   v0: 259.4\n";
  CalibrationFile f = ReadCalibrationFile(TempFile("kb.yaml", kb));
  ASSERT_TRUE(f.camera);
  EXPECT_EQ(f.camera->distortion, DistortionModel::kFisheye);
  EXPECT_EQ(f.camera->fisheye.k1, -0.061);
  EXPECT_EQ(f.camera->fisheye.k4, -0.030);
  EXPECT_EQ(f.camera->fx, 413.3);
  EXPECT_EQ(f.camera->cy, 259.4);

  using Err = std::pair<std::string, std::string>;
  EXPECT_EQ(ErrorOf("mei.yaml", "%YAML:1.0\nmodel_type: MEI\nimage_width: 640\nimage_height: 480\n"),
            (Err{":2", "model_type MEI (camodocal): lasertwin reads PINHOLE and KANNALA_BRANDT cameras; MEI is another "
                       "projection"}));
  // k2..k5 where camodocal does not read them (it would run without distortion).
  EXPECT_EQ(ErrorOf("kbmoved.yaml", "%YAML:1.0\nmodel_type: KANNALA_BRANDT\nimage_width: 640\nimage_height: 512\n"
                                    "distortion_parameters:\n   k2: -0.061\n   k3: -0.0038\n   k4: 0.027\n   k5: -0.03\n"
                                    "projection_parameters:\n   mu: 413.3\n   mv: 413.7\n   u0: 305.9\n   v0: 259.4\n")
                .first,
            ":5");
}

// One camera written in each form reads as the same camera.
TEST(CalibrationFileFormats, SameCameraInEveryFormat) {
  const std::vector<std::pair<std::string, std::string>> files = {
      {"opencv.yml",
       "%YAML:1.0\n---\nimage_width: 320\nimage_height: 256\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n"
       "   dt: d\n   data: [ 402.5, 0., 159.25, 0., 403.75, 127.5, 0., 0., 1. ]\ndistortion_coefficients: !!opencv-matrix\n"
       "   rows: 1\n   cols: 4\n   dt: d\n   data: [ -0.125, 0.0625, 0.001, -0.002 ]\n"},
      {"ros.yaml",
       "image_width: 320\nimage_height: 256\ncamera_name: scanner\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
       "  data: [402.5, 0, 159.25, 0, 403.75, 127.5, 0, 0, 1]\ndistortion_model: plumb_bob\ndistortion_coefficients:\n"
       "  rows: 1\n  cols: 5\n  data: [-0.125, 0.0625, 0.001, -0.002, 0]\n"},
      {"kalibr.yaml",
       "cam0:\n  camera_model: pinhole\n  intrinsics: [402.5, 403.75, 159.25, 127.5]\n  distortion_model: radtan\n"
       "  distortion_coeffs: [-0.125, 0.0625, 0.001, -0.002]\n  resolution: [320, 256]\n"},
      {"camodocal.yaml",
       "%YAML:1.0\n---\nmodel_type: PINHOLE\ncamera_name: camera\nimage_width: 320\nimage_height: 256\n"
       "distortion_parameters:\n   k1: -0.125\n   k2: 0.0625\n   p1: 0.001\n   p2: -0.002\nprojection_parameters:\n"
       "   fx: 402.5\n   fy: 403.75\n   cx: 159.25\n   cy: 127.5\n"},
  };
  for (const auto& [name, text] : files) {
    const CalibrationFile c = ReadCalibrationFile(TempFile(name, text));
    ASSERT_TRUE(c.camera) << name;
    const CalibratedCamera& k = *c.camera;
    EXPECT_EQ(std::vector<double>({double(k.width), double(k.height), k.fx, k.fy, k.cx, k.cy}),
              std::vector<double>({320, 256, 402.5, 403.75, 159.25, 127.5}))
        << name;
    EXPECT_EQ(k.distortion, DistortionModel::kBrownConrady) << name;
    EXPECT_EQ(std::vector<double>({k.brown_conrady.k1, k.brown_conrady.k2, k.brown_conrady.p1, k.brown_conrady.p2,
                                   k.brown_conrady.k3}),
              std::vector<double>({-0.125, 0.0625, 0.001, -0.002, 0}))
        << name;
  }
}

// OpenCV's stereo_calib sample (intrinsics.yml: M1 D1 M2 D2, no image size),
// and a file with nothing to read, are refused. (Before: every key ignored
// with a warning each, and the laser step went on with the run's true camera.)
TEST(CalibrationFileFormats, StereoAndEmptyFilesAreRefused) {
  const std::string k = "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 8.3e+02, 0., 5.8e+02, 0., 8.3e+02, "
                        "4.7e+02, 0., 0., 1. ]\n";
  const std::string d = "!!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ -0.37, 0.16, 0., 0., -0.03 ]\n";
  const auto stereo = ErrorOf("intrinsics.yml", "%YAML:1.0\n---\nM1: " + k + "D1: " + d + "M2: " + k + "D2: " + d);
  EXPECT_EQ(stereo.first, "");
  EXPECT_THAT(stereo.second, HasSubstr("an OpenCV stereo calibration (M1 D1 M2 D2 or K1 D1 K2 D2, without the image "
                                       "size): lasertwin reads one camera"));
  EXPECT_EQ(ErrorOf("empty.yml", "%YAML:1.0\n---\nboard_width: 8\nsquare_size: 22.2\n"),
            (std::pair<std::string, std::string>{
                "", "holds nothing lasertwin reads: no camera (camera_matrix, image_width, image_height), laser_planes, "
                    "tool_from_cam or depth_min_mm/depth_max_mm (its keys: board_width, square_size)"}));
  // Not YAML at all (OcamCalib's calib_results.txt): the YAML error, naming what is read.
  const auto ocam = ErrorOf("calib_results.txt",
                            "#polynomial coefficients for the DIRECT mapping function\n\n"
                            "5 -2.716972e+02 0.000000e+00 -2.741744e-06 1.840940e-06 -8.024838e-10 \n");
  EXPECT_EQ(ocam.first, ":3");
  EXPECT_THAT(ocam.second, HasSubstr("expected a calibration file: OpenCV FileStorage YAML or XML, or the camera file of "
                                     "ROS (camera_info), Kalibr (camchain) or camodocal"));
  // An OpenCV file (%YAML: first) that is no YAML: the tree's error as it is.
  const auto opencv = ErrorOf("broken.yml", "%YAML:1.0\n---\nimage_width: 640\nnote: [ 1, 2\n");
  EXPECT_EQ(opencv.first, ":4");
  EXPECT_THAT(opencv.second, HasSubstr("missing ']'"));
  EXPECT_THAT(opencv.second, ::testing::Not(HasSubstr("expected a calibration file")));
}

// OpenCV's entries and matrices and other tools' nodes are read by one set of
// checks (pipeline/yaml_scalar.h), with the same messages at file:line. (Before:
// an OpenCV matrix's rows were 'a positive integer' and its data 'not a finite
// number: ...', a ROS matrix's 'an integer in [0, 1000]' and 'must be a finite number'.)
TEST(CalibrationFileFormats, OneSetOfValueChecks) {
  const std::string m = "!!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n";
  EXPECT_EQ(ErrorOf("r.yml", "%YAML:1.0\nlaser_planes: " + m.substr(0, m.find("rows")) + "rows: x\n   cols: 4\n   dt: d\n"
                             "   data: [ 0., 1., 0., 0. ]\n"),
            (std::pair<std::string, std::string>{":3", "rows must be an integer in [1, 100000000], got 'x'"}));
  EXPECT_EQ(ErrorOf("d.yml", "%YAML:1.0\nlaser_planes: " + m + "   data: [ 0., x, 0., 0. ]\n"),
            (std::pair<std::string, std::string>{":6", "data value 1 must be a finite number, got 'x'"}));
  const std::string ros = "image_width: 640\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n";
  EXPECT_EQ(ErrorOf("ost.yaml", ros + "  data: [500, x, 320, 0, 500, 240, 0, 0, 1]\n"),
            (std::pair<std::string, std::string>{":6", "camera_matrix: data value 1 must be a finite number, got 'x'"}));
  // The same words for an entry (OpenCV) and a node (ROS): a quoted number is a string.
  const std::string k = "camera_matrix: " + m.substr(0, m.find("rows")) + "rows: 3\n   cols: 3\n   dt: d\n"
                        "   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n";
  EXPECT_EQ(ErrorOf("w.yml", "%YAML:1.0\nimage_width: \"640\"\nimage_height: 480\n" + k),
            (std::pair<std::string, std::string>{":2", "image_width must be an integer in [1, 65536], got '640'"}));
  EXPECT_EQ(ErrorOf("ost.yaml", "image_width: \"640\"\n" + ros.substr(ros.find("image_height")) +
                                    "  data: [500, 0, 320, 0, 500, 240, 0, 0, 1]\n"),
            (std::pair<std::string, std::string>{":1", "image_width must be an integer in [1, 65536], got '640'"}));
  EXPECT_EQ(ErrorOf("m.yml", "%YAML:1.0\nimage_width: 640\nimage_height: 480\ndistortion_model: [a]\n" + k),
            (std::pair<std::string, std::string>{":4", "distortion_model must be a string"}));
}

// COLMAP's cameras.txt: one camera, its principal point moved by half a pixel
// (COLMAP puts pixel (0,0)'s centre at (0.5, 0.5)). (Before: refused, "the
// first line must be %YAML:1.0".)
TEST(CalibrationFileFormats, ColmapCameras) {
  const std::string head = "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
  CalibrationFile s = ReadCalibrationFile(TempFile("cameras.txt", head + "1 SIMPLE_RADIAL 800 1200 2468.36 400 600 -0.0556541\n"));
  ASSERT_TRUE(s.camera);
  EXPECT_EQ(std::vector<double>({double(s.camera->width), double(s.camera->height), s.camera->fx, s.camera->fy,
                                 s.camera->cx, s.camera->cy, s.camera->brown_conrady.k1}),
            std::vector<double>({800, 1200, 2468.36, 2468.36, 399.5, 599.5, -0.0556541}));
  CalibrationFile o = ReadCalibrationFile(
      TempFile("opencv.txt", head + "3 OPENCV 640 480 500.5 501 320.25 240.75 -0.2 0.05 0.001 -0.002\n"));
  ASSERT_TRUE(o.camera);
  EXPECT_EQ(std::vector<double>({o.camera->fx, o.camera->fy, o.camera->cx, o.camera->cy, o.camera->brown_conrady.p2}),
            std::vector<double>({500.5, 501, 319.75, 240.25, -0.002}));
  CalibrationFile f = ReadCalibrationFile(
      TempFile("fisheye.txt", head + "1 OPENCV_FISHEYE 640 480 300 300 320 240 0.1 -0.01 0.001 -0.0001\n"));
  ASSERT_TRUE(f.camera);
  EXPECT_EQ(f.camera->distortion, DistortionModel::kFisheye);
  EXPECT_EQ(f.camera->fisheye.k4, -0.0001);
  using Err = std::pair<std::string, std::string>;
  EXPECT_EQ(ErrorOf("several.txt", head + "1 SIMPLE_PINHOLE 1080 1920 1889.86 540 960\n2 SIMPLE_PINHOLE 1080 1920 1820.24 540 960\n"),
            (Err{":4", "a COLMAP cameras.txt of 2 cameras: give --calib-camera with the scanner camera's: '1', '2'"}));
  EXPECT_EQ(ErrorOf("fov.txt", head + "1 FOV 640 480 500 500 320 240 0.9\n").first, ":3");
  EXPECT_EQ(ErrorOf("count.txt", head + "1 PINHOLE 640 480 500 500 320\n"),
            (Err{":3", "COLMAP PINHOLE has 4 parameters, got 3"}));
}

}  // namespace
}  // namespace lt

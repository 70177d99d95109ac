// Calibration files (OpenCV FileStorage YAML): exact round trips through the
// writer and reader, a file in the form OpenCV's calibration sample writes,
// and one error per kind of bad input, each naming file:line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "pipeline/calibration_file.h"
#include "pipeline/opencv_yaml.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

CalibrationFile Example() {
  CalibrationFile c;
  CalibratedCamera cam;
  cam.width = 1280;
  cam.height = 1024;
  cam.fx = 1851.8541666666667;
  cam.fy = 1852.0000000000002;
  cam.cx = 639.5 + 1.0 / 3.0;
  cam.cy = 511.5 - 1e-7;
  cam.distortion = DistortionModel::kBrownConrady;
  cam.brown_conrady = {-0.123456789012345, 0.0456, 1.0 / 3000.0, -2.5e-5, 1e-3};
  c.camera = cam;
  c.laser_planes.push_back(Plane::FromPointNormal({0, 0, 0.08}, {0, 0.8944, 0.4472}));
  c.laser_planes.push_back(Plane::FromPointNormal({0.001, 0.002, 0.09}, {0.01, 0.9, 0.43}));
  c.laser_planes.push_back({{0, 0, 1}, -0.1});
  Pose t = Pose::Identity();
  t.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(0.012, -0.034, 0.1567);
  c.tool_from_cam = t;
  return c;
}

// Writes text to a temporary file named `name`.
fs::path TempFile(const std::string& name, const std::string& text) {
  fs::path dir = fs::temp_directory_path() / ("lt_calib_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::path p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

TEST(CalibrationFile, RoundTripIsExact) {
  const CalibrationFile c = Example();
  const std::string text = FormatCalibrationFile(c);
  EXPECT_EQ(text.rfind("%YAML:1.0\n---\n", 0), 0u);
  EXPECT_THAT(text, HasSubstr("camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ "));
  fs::path p = TempFile("roundtrip.yml", "");
  WriteCalibrationFile(p, c);
  CalibrationFile r = ReadCalibrationFile(p);
  ASSERT_TRUE(r.camera);
  EXPECT_EQ(r.camera->width, 1280);
  EXPECT_EQ(r.camera->height, 1024);
  EXPECT_EQ(r.camera->fx, c.camera->fx);
  EXPECT_EQ(r.camera->fy, c.camera->fy);
  EXPECT_EQ(r.camera->cx, c.camera->cx);
  EXPECT_EQ(r.camera->cy, c.camera->cy);
  EXPECT_EQ(r.camera->distortion, DistortionModel::kBrownConrady);
  const auto& a = r.camera->brown_conrady;
  const auto& b = c.camera->brown_conrady;
  EXPECT_EQ(a.k1, b.k1);
  EXPECT_EQ(a.k2, b.k2);
  EXPECT_EQ(a.p1, b.p1);
  EXPECT_EQ(a.p2, b.p2);
  EXPECT_EQ(a.k3, b.k3);
  ASSERT_EQ(r.laser_planes.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(r.laser_planes[k].n, c.laser_planes[k].n) << k;
    EXPECT_EQ(r.laser_planes[k].d, c.laser_planes[k].d) << k;
  }
  ASSERT_TRUE(r.tool_from_cam);
  EXPECT_EQ(r.tool_from_cam->matrix(), c.tool_from_cam->matrix());
  EXPECT_TRUE(r.ignored_keys.empty());
  // Writing what was read gives the same text.
  EXPECT_EQ(FormatCalibrationFile(r), text);
}

// The scanner's working range (depth_min_mm, depth_max_mm) reads back as
// written, in YAML and XML, and is no ignored key.
TEST(CalibrationFile, WorkingRangeRoundTrips) {
  CalibrationFile c = Example();
  c.depth_range = DepthRange{0.085, 0.12};
  const std::string text = FormatCalibrationFile(c);
  EXPECT_THAT(text, HasSubstr("depth_min_mm: 85"));
  for (const char* name : {"range.yml", "range.xml"}) {
    fs::path p = TempFile(name, "");
    WriteCalibrationFile(p, c);
    const CalibrationFile r = ReadCalibrationFile(p);
    ASSERT_TRUE(r.depth_range) << name;
    EXPECT_EQ(r.depth_range->near_m, 0.085) << name;
    EXPECT_EQ(r.depth_range->far_m, 0.12) << name;
    EXPECT_TRUE(r.ignored_keys.empty()) << name;
    EXPECT_EQ(FormatCalibrationFile(r), text) << name;
  }
}

// A name ending in .xml is written in OpenCV's XML form (before: YAML under
// any name), exactly as the YAML form reads back; other extensions are refused
// before anything is written.
TEST(CalibrationFile, FormIsChosenByTheExtension) {
  const CalibrationFile c = Example();
  const std::string xml = FormatCalibrationFile(c, StorageFormat::kXml);
  EXPECT_EQ(xml.rfind("<?xml version=\"1.0\"?>\n<opencv_storage>\n<image_width>1280</image_width>\n", 0), 0u);
  EXPECT_THAT(xml, HasSubstr("<camera_matrix type_id=\"opencv-matrix\">\n  <rows>3</rows>\n  <cols>3</cols>\n"
                             "  <dt>d</dt>\n  <data>\n    1851.8541666666667 0. "));
  EXPECT_THAT(xml, HasSubstr("<distortion_model>brown_conrady</distortion_model>\n"));
  EXPECT_EQ(xml.substr(xml.size() - 18), "</opencv_storage>\n");
  for (const char* name : {"c.xml", "c.XML"}) {
    const fs::path p = TempFile(name, "");
    WriteCalibrationFile(p, c);
    std::ifstream in(p);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text, xml) << name;
    // Read back: the same values as the YAML form's, to the bit.
    EXPECT_EQ(FormatCalibrationFile(ReadCalibrationFile(p)), FormatCalibrationFile(c)) << name;
  }
  for (const char* name : {"c.yaml", "c.YML"}) EXPECT_EQ(CalibrationFileFormat(name), StorageFormat::kYaml) << name;
  for (const char* name : {"c.json", "calib", "c.yaml.gz"}) {
    const fs::path p = fs::path(TempFile("x", "")).parent_path() / name;
    fs::remove(p);
    try {
      WriteCalibrationFile(p, c);
      ADD_FAILURE() << name << " was written";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(p.string() + ": "));
      EXPECT_THAT(e.what(), HasSubstr("OpenCV YAML (.yaml, .yml) or OpenCV XML (.xml)"));
    }
    EXPECT_FALSE(fs::exists(p)) << name;
  }
  // Strings that need quoting and entities read back as written.
  OpenCvYamlWriter w(StorageFormat::kXml);
  w.String("s", "two words <&> \"q\" 'a'");
  w.String("t", "fisheye");
  w.String("n", "12");
  w.Integer("i", -3);
  w.Number("r", 2.0);
  const OpenCvYaml back = OpenCvYaml::Parse(w.text(), "w.xml");
  EXPECT_EQ(back.String(*back.Find("s")), "two words <&> \"q\" 'a'");
  EXPECT_EQ(back.String(*back.Find("t")), "fisheye");
  EXPECT_TRUE(back.Find("n")->quoted);
  EXPECT_EQ(back.Integer(*back.Find("i"), -10, 10), -3);
  EXPECT_EQ(back.Number(*back.Find("r")), 2.0);
}

TEST(CalibrationFile, FisheyeAndNoDistortionRoundTrip) {
  CalibrationFile c;
  CalibratedCamera cam;
  cam.width = 640;
  cam.height = 480;
  cam.fx = cam.fy = 300;
  cam.cx = 319.5;
  cam.cy = 239.5;
  cam.distortion = DistortionModel::kFisheye;
  cam.fisheye = {0.01, -0.002, 3e-4, -1e-5};
  c.camera = cam;
  CalibrationFile r = ReadCalibrationFile(TempFile("fisheye.yml", FormatCalibrationFile(c)));
  ASSERT_TRUE(r.camera);
  EXPECT_EQ(r.camera->distortion, DistortionModel::kFisheye);
  EXPECT_EQ(r.camera->fisheye.k1, 0.01);
  EXPECT_EQ(r.camera->fisheye.k4, -1e-5);
  EXPECT_TRUE(r.laser_planes.empty());
  EXPECT_FALSE(r.tool_from_cam);
  // The camera builds with the file's distortion.
  Camera built = r.MakeCamera(CameraParams{}, "fisheye.yml");
  EXPECT_EQ(built.distortion_model(), DistortionModel::kFisheye);
  EXPECT_EQ(built.width(), 640);

  c.camera->distortion = DistortionModel::kNone;
  r = ReadCalibrationFile(TempFile("pinhole.yml", FormatCalibrationFile(c)));
  EXPECT_EQ(r.camera->distortion, DistortionModel::kNone);
}

TEST(CalibrationFile, ReadsOpenCvSampleOutput) {
  // As OpenCV's camera calibration sample writes it (cv::FileStorage): 5x1
  // distortion, reals like "0." and "1.", data over several lines, extra keys.
  const std::string text = R"(%YAML:1.0
---
calibration_time: "Tue 21 Nov 2023 10:00:00 CET"
nframes: 12
image_width: 640
image_height: 480
board_width: 9
board_height: 6
square_size: 2.5000000000000001e-02
flags: 0
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 6.5746697944293521e+02, 0., 3.1950000000000000e+02, 0.,
       6.5746697944293521e+02, 2.3950000000000000e+02, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 5
   cols: 1
   dt: d
   data: [ -4.1802327176423804e-01, 5.0715244063187526e-01, 0., 0.,
       -5.7843597214487474e-01 ]
avg_reprojection_error: 3.9259716356036523e-01
per_view_reprojection_errors: !!opencv-matrix
   rows: 2
   cols: 1
   dt: f
   data: [ 1.92965463e-01, 1.88124001e-01 ]
# the laser part, as lasertwin writes it
laser_planes: !!opencv-matrix
   rows: 1
   cols: 4
   dt: d
   data: [ 0., 2., 1., -0.08 ]   # not normalised: the reader divides by |n|
image_points: !!opencv-nd-matrix
   sizes: [ 2, 1 ]
   dt: "2f"
   data: [ 1., 2., 3., 4. ]
)";
  CalibrationFile c = ReadCalibrationFile(TempFile("opencv.yml", text));
  ASSERT_TRUE(c.camera);
  EXPECT_EQ(c.camera->width, 640);
  EXPECT_EQ(c.camera->fx, 6.5746697944293521e+02);
  EXPECT_EQ(c.camera->cx, 319.5);
  EXPECT_EQ(c.camera->distortion, DistortionModel::kBrownConrady);
  EXPECT_EQ(c.camera->brown_conrady.k1, -4.1802327176423804e-01);
  EXPECT_EQ(c.camera->brown_conrady.k3, -5.7843597214487474e-01);
  ASSERT_EQ(c.laser_planes.size(), 1u);
  EXPECT_NEAR(c.laser_planes[0].n.y(), 2 / std::sqrt(5.0), 1e-16);
  EXPECT_NEAR(c.laser_planes[0].d, -0.08 / std::sqrt(5.0), 1e-17);
  EXPECT_EQ(c.ignored_keys,
            (std::vector<std::string>{"calibration_time", "nframes", "board_width", "board_height", "square_size",
                                      "flags", "avg_reprojection_error", "per_view_reprojection_errors",
                                      "image_points"}));
}

// OpenCV's camera calibration sample marks a fisheye calibration by
// `fisheye_model: 1`, with 4x1 coefficients k1..k4 and no distortion_model:
// they are cv::fisheye's, not Brown-Conrady's k1 k2 p1 p2. (Before: read as
// Brown-Conrady, silently, and fisheye_model listed as ignored.)
TEST(CalibrationFile, OpenCvSampleFisheyeModelFlag) {
  const std::string head = R"(%YAML:1.0
---
image_width: 1024
image_height: 768
flags: 0
)";
  const std::string tail = R"(camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 3.3000000000000000e+02, 0., 5.1730000000000001e+02, 0.,
       3.3100000000000000e+02, 3.8060000000000002e+02, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 4
   cols: 1
   dt: d
   data: [ 5.0000000000000003e-02, -1.0000000000000000e-02,
       2.0000000000000000e-03, 0. ]
)";
  CalibrationFile f = ReadCalibrationFile(TempFile("fisheye_flag.yml", head + "fisheye_model: 1\n" + tail));
  ASSERT_TRUE(f.camera);
  EXPECT_EQ(f.camera->distortion, DistortionModel::kFisheye);
  EXPECT_EQ(f.camera->fisheye.k1, 0.05);
  EXPECT_EQ(f.camera->fisheye.k3, 0.002);
  EXPECT_EQ(f.ignored_keys, std::vector<std::string>{"flags"});
  CalibrationFile b = ReadCalibrationFile(TempFile("pinhole_flag.yml", head + "fisheye_model: 0\n" + tail));
  ASSERT_TRUE(b.camera);
  EXPECT_EQ(b.camera->distortion, DistortionModel::kBrownConrady);
  EXPECT_EQ(b.camera->brown_conrady.p1, 0.002);
  // A flag that contradicts distortion_model is an error at its line.
  try {
    ReadCalibrationFile(TempFile("both.yml", head + "fisheye_model: 1\ndistortion_model: brown_conrady\n" + tail));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("both.yml:6: fisheye_model 1 contradicts distortion_model brown_conrady"),
              std::string::npos)
        << e.what();
  }
}

// OpenCV writes the XML form when the file name ends in .xml: the same keys
// as child elements of <opencv_storage>, matrices with type_id
// "opencv-matrix" and white-space separated data, strings in quotes.
// (Before: refused, "the first line must be %YAML:1.0".)
TEST(CalibrationFile, ReadsOpenCvXml) {
  const std::string text = R"(<?xml version="1.0"?>
<opencv_storage>
<calibration_time>"Thu 26 Nov 2026 10:00:00 UTC"</calibration_time>
<image_width>1024</image_width>
<image_height>768</image_height>
<!-- a comment -->
<fisheye_model>0</fisheye_model>
<camera_matrix type_id="opencv-matrix">
  <rows>3</rows>
  <cols>3</cols>
  <dt>d</dt>
  <data>
    8.8000000000000000e+02 0. 5.1730000000000001e+02 0.
    8.8400000000000000e+02 3.8060000000000002e+02 0. 0. 1.</data></camera_matrix>
<distortion_coefficients type_id="opencv-matrix">
  <rows>5</rows>
  <cols>1</cols>
  <dt>d</dt>
  <data>
    -2.8e-01 1.1e-01 6.0e-04 -4.0e-04 0.</data></distortion_coefficients>
<extrinsic_parameters type_id="opencv-matrix">
  <rows>1</rows>
  <cols>6</cols>
  <dt>f</dt>
  <data>
    1. 2. 3. 4. 5. 6.</data></extrinsic_parameters>
<image_points type_id="opencv-nd-matrix">
  <sizes>2 1</sizes>
  <dt>"2f"</dt>
  <data>1. 2. 3. 4.</data></image_points>
</opencv_storage>
)";
  CalibrationFile c = ReadCalibrationFile(TempFile("opencv.xml", text));
  ASSERT_TRUE(c.camera);
  EXPECT_EQ(c.camera->width, 1024);
  EXPECT_EQ(c.camera->height, 768);
  EXPECT_EQ(c.camera->fx, 880);
  EXPECT_EQ(c.camera->cy, 3.8060000000000002e+02);
  EXPECT_EQ(c.camera->distortion, DistortionModel::kBrownConrady);
  EXPECT_EQ(c.camera->brown_conrady.k1, -0.28);
  EXPECT_EQ(c.camera->brown_conrady.p2, -4e-4);
  EXPECT_EQ(c.ignored_keys,
            (std::vector<std::string>{"calibration_time", "extrinsic_parameters", "image_points"}));
  // Errors name the file and line.
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"<?xml version=\"1.0\"?>\n<storage>\n</storage>\n", "bad.xml:2: not an OpenCV FileStorage XML file"},
      {"<?xml version=\"1.0\"?>\n<opencv_storage>\n<image_width>1024</image_height>\n</opencv_storage>\n",
       "bad.xml:3: </image_height> closes <image_width>"},
      {"<?xml version=\"1.0\"?>\n<opencv_storage>\n<laser_planes type_id=\"opencv-matrix\">\n<rows>1</rows><cols>4</cols>"
       "<dt>d</dt>\n<data>0. 1. x 0.</data></laser_planes>\n</opencv_storage>\n",
       "bad.xml:5: data value 2 must be a finite number, got 'x'"},
      {"<?xml version=\"1.0\"?>\n<opencv_storage>\n<image_width>1024</image_width>\n", "bad.xml:2: <opencv_storage> is not closed"},
  };
  for (const auto& [xml, message] : bad) {
    try {
      ReadCalibrationFile(TempFile("bad.xml", xml));
      ADD_FAILURE() << "no error for: " << xml;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

TEST(OpenCvYaml, ScalarsAndStrings) {
  OpenCvYaml y = OpenCvYaml::Parse(
      "%YAML:1.0\n---\na: 12\nb: -3.5e-2  # comment\nc: \"quoted # not a comment\"\nd: 'it''s'\ne: plain text\n",
      "x.yml");
  EXPECT_EQ(y.Integer(*y.Find("a"), 0, 100), 12);
  EXPECT_EQ(y.Number(*y.Find("b")), -0.035);
  EXPECT_EQ(y.String(*y.Find("c")), "quoted # not a comment");
  EXPECT_EQ(y.String(*y.Find("d")), "it's");
  EXPECT_EQ(y.String(*y.Find("e")), "plain text");
  EXPECT_THROW(y.Number(*y.Find("c")), InputError);  // a quoted string is not a number
  EXPECT_EQ(y.Find("f"), nullptr);
  OpenCvYamlWriter w;
  w.String("s", "two words");
  w.String("t", "fisheye");
  w.String("n", "12");  // would read as a number unquoted
  w.Number("r", 2.0);
  OpenCvYaml back = OpenCvYaml::Parse(w.text(), "w.yml");
  EXPECT_EQ(back.String(*back.Find("s")), "two words");
  EXPECT_EQ(back.String(*back.Find("t")), "fisheye");
  EXPECT_TRUE(back.Find("n")->quoted);
  EXPECT_THAT(w.text(), HasSubstr("r: 2.\n"));
  EXPECT_THROW(w.Number("bad", std::nan("")), std::invalid_argument);
}

struct BadFile {
  std::string text;
  std::string where;    // ":LINE" after the file name, or "" for the file alone
  std::string message;  // part of the message
};

TEST(CalibrationFile, BadFilesNameTheFileAndLine) {
  const std::string head = "%YAML:1.0\n---\n";
  const std::string cam = "image_width: 640\nimage_height: 480\n";
  const std::string k = "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., 320., 0., "
                        "500., 240., 0., 0., 1. ]\n";
  const std::vector<BadFile> cases = {
      {"", ":1", "not an OpenCV FileStorage YAML file"},
      {"camera_matrix: 1\n", ":1", "not an OpenCV FileStorage YAML file"},
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n   data: [ 0., 1., 0. ]\n", ":7",
       "is 1x4 and needs 4 values, got 3"},
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n   data: [ 0., 1., 0. ]\n", ":3",
       "laser_planes must be N x 4"},
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n   data: [ 0., .Nan, 0., 1. ]\n", ":7",
       "data value 1 must be a finite number, got '.Nan'"},
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n   data: [ 0., 0., 0., 1. ]\n", ":3",
       "plane 0 has a zero normal"},
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: 5d\n   data: [ 0., 0., 1., 1. ]\n", ":6",
       "dt must be d, f, i, u, s, w or c, with an optional channel count"},
      // Several channels read (OpenCV's sample writes its image points as "2f"), but not where one is needed.
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 2\n   dt: 2d\n   data: [ 0., 0., 1., 1. ]\n", ":3",
       "laser_planes must have one channel (dt d), got 2 (dt 2d)"},
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 4\n   type: d\n   data: [ 0., 0., 1., 1. ]\n", ":6",
       "unknown matrix key 'type'"},
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n   data: [ 0., 0., 1., 1.\n", ":7",
       "missing ']'"},
      {head + "laser_planes: !!opencv-matrix\n   rows: 1\n   dt: d\n   data: [ 0., 0., 1., 1. ]\n", ":3",
       "needs rows, cols, dt and data"},
      {head + k, "", "missing image_width, image_height"},
      {head + cam + "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 1., 320., 0., "
                    "500., 240., 0., 0., 1. ]\n",
       ":5", "skew"},
      {head + cam + "camera_matrix: !!opencv-matrix\n   rows: 2\n   cols: 2\n   dt: d\n   data: [ 1., 0., 0., 1. ]\n",
       ":5", "camera_matrix must be 3x3, got 2x2"},
      {head + cam + k + "distortion_model: fisheye\ndistortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n"
                        "   dt: d\n   data: [ 0., 0., 0., 0., 0. ]\n",
       ":11", "fisheye distortion_coefficients must have 4 values"},
      {head + cam + k + "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 8\n   dt: d\n"
                        "   data: [ 0., 0., 0., 0., 0., 0.1, 0., 0. ]\n",
       ":10", "distortion_coefficients element 6: k4 is not modelled (only k1 k2 p1 p2 k3): must be 0, got 0.1"},
      // OpenCV writes 4, 5, 8, 12 or 14 (as a scene file's coefficients); 6 was read.
      {head + cam + k + "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 6\n   dt: d\n"
                        "   data: [ 0., 0., 0., 0., 0., 0. ]\n",
       ":10", "distortion_coefficients must have 4, 5, 8, 12 or 14 elements"},
      {head + cam + k + "distortion_model: rational\n", ":10", "distortion_model must be brown_conrady (plumb_bob, rational_polynomial, radtan) or fisheye"},
      {head + cam + k + "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
                        "   data: [ -3., 0., 0., 0., 0. ]\n",
       "", "distortion"},  // folds inside the image
      {head + "image_width: 0\nimage_height: 480\n" + k, ":3", "image_width must be an integer in [1, 65536], got '0'"},
      {head + "tool_from_cam: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n"
              "   data: [ 1., 0., 0., 0., 0., 2., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1. ]\n",
       ":3", "must be a rotation"},
      {head + "tool_from_cam: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n"
              "   data: [ 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 1., 1. ]\n",
       ":3", "the last row must be 0 0 0 1"},
      {head + "a: 1\na: 2\n", ":4", "duplicate key 'a'"},
      {head + "a: 1\n  b: 2\n", ":4", "unexpected indented line"},
      {head + "\tcamera_matrix: 1\n", ":3", "tab in indentation"},
      {head + "just text\n", ":3", "expected 'key: value'"},
      {head + "- 1\n", ":3", "top-level sequences are not supported"},
      {head + "s: \"open\n", ":3", "unterminated quoted string"},
      {head + "depth_min_mm: 60\n", ":3", "the working range needs both depth_min_mm and depth_max_mm"},
      {head + "depth_min_mm: 120\ndepth_max_mm: 60\n", ":4", "the depth range must be 0 < MIN < MAX"},
      {head + "depth_min_mm: near\ndepth_max_mm: 60\n", ":3", "depth_min_mm must be a finite number, got 'near'"},
  };
  int i = 0;
  for (const BadFile& c : cases) {
    fs::path p = TempFile("bad" + std::to_string(i++) + ".yml", c.text);
    try {
      ReadCalibrationFile(p);
      ADD_FAILURE() << "accepted:\n" << c.text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where(), p.string() + c.where) << c.text << "\n" << e.what();
      EXPECT_THAT(e.message(), HasSubstr(c.message)) << c.text;
    }
  }
}

TEST(CalibrationFile, MissingOrUnreadableFile) {
  const fs::path missing = fs::temp_directory_path() / "lt_no_such_calibration.yml";
  try {
    ReadCalibrationFile(missing);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.what(), missing.string() + ": cannot open file");
  }
  try {
    ReadCalibrationFile(fs::temp_directory_path());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("is a folder, not a calibration file"));
  }
}

}  // namespace
}  // namespace lt

// Reading run folders: manifest lines (laser/bright frames, poses, bit depths),
// rig.json and the scene.json fallback, and clean errors naming file:line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "pipeline/run_folder_reader.h"
#include "sensor/rig.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

fs::path NewRun(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("lt_runreader_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void Write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

const char* kDimLine =
    R"({"index":0,"label":"dim","shutter":{"laser_on":true,"led_on":false,"pattern_on":false},"lit_fraction":{"laser":1.0,"led":0.0,"pattern":0.0},"files":{"image":"frames/000000.png","centers":"gt/000000_centers.csv"},"world_from_cam":{"translation_m":[0.004,-0.002,0.083],"rotation_quat_wxyz":[0,1,0,0]},"gt_axis":"cols","bit_depth":10,"png_bit_depth":16,"t_start_s":0.0,"t_end_s":5e-05,"stats":{"rays":1}})";
const char* kBrightLine =
    R"({"index":1,"label":"bright","shutter":{"laser_on":false},"lit_fraction":{"laser":0.0},"files":{"image":"frames/000001.png"},"bit_depth":10,"png_bit_depth":8})";

TEST(RunFolderReader, ReadsManifestLines) {
  fs::path run = NewRun("ok");
  // Lines in any order, blank lines allowed; frames come back sorted.
  Write(run / "manifest.jsonl", std::string(kBrightLine) + "\n\n" + kDimLine + "\n");
  std::vector<RunFrame> frames = ReadRunManifest(run);
  ASSERT_EQ(frames.size(), 2u);
  const RunFrame& dim = frames[0];
  EXPECT_EQ(dim.index, 0);
  EXPECT_EQ(dim.label, "dim");
  EXPECT_TRUE(dim.IsLaserFrame());
  EXPECT_EQ(dim.image, run / "frames/000000.png");
  ASSERT_TRUE(dim.gt_centers);
  EXPECT_EQ(*dim.gt_centers, run / "gt/000000_centers.csv");
  ASSERT_TRUE(dim.world_from_cam);
  EXPECT_TRUE(dim.world_from_cam->translation().isApprox(Eigen::Vector3d(0.004, -0.002, 0.083)));
  // Quaternion (0, 1, 0, 0): 180 degrees about x.
  EXPECT_TRUE(dim.world_from_cam->linear().isApprox(Eigen::Vector3d(1, -1, -1).asDiagonal().toDenseMatrix()));
  ASSERT_TRUE(dim.gt_axis);
  EXPECT_EQ(*dim.gt_axis, SearchAxis::kCols);
  EXPECT_EQ(dim.bit_depth, 10);
  EXPECT_EQ(dim.t_end_s, 5e-5);
  EXPECT_EQ(dim.where, (run / "manifest.jsonl").string() + ":3");
  // 10-bit raw DN in a 16-bit PNG: full scale 1023; an 8-bit PNG holds the top 8 bits.
  EXPECT_EQ(dim.FullScale(65535), 1023);
  EXPECT_EQ(frames[1].FullScale(255), 255);
  EXPECT_FALSE(frames[1].IsLaserFrame());
  EXPECT_FALSE(frames[1].world_from_cam);
}

TEST(RunFolderReader, LaserFrameRules) {
  fs::path run = NewRun("rules");
  Write(run / "manifest.jsonl",
        R"({"index":0,"files":{"image":"a.png"}})"
        "\n"
        R"({"index":1,"files":{"image":"b.png"},"shutter":{"laser_on":false},"lit_fraction":{"laser":0.25}})"
        "\n"
        R"({"index":2,"files":{"image":"c.png"},"shutter":{"laser_on":false}})"
        "\n"
        R"({"index":3,"files":{"image":"d.png"},"lit_fraction":{"laser":0.5}})"
        "\n"
        R"({"index":4,"files":{"image":"e.png"},"lit_fraction":{"laser":0}})"
        "\n");
  std::vector<RunFrame> f = ReadRunManifest(run);
  ASSERT_EQ(f.size(), 5u);
  EXPECT_TRUE(f[0].IsLaserFrame());   // no shutter information: a laser scanner's frame
  EXPECT_FALSE(f[1].IsLaserFrame());  // a bright frame the laser bled into (sync error): colour, not stripes
  EXPECT_FALSE(f[2].IsLaserFrame());
  EXPECT_TRUE(f[3].IsLaserFrame());   // no commanded state: the laser lit the frame
  EXPECT_FALSE(f[4].IsLaserFrame());
  EXPECT_EQ(f[0].FullScale(65535), 65535);  // bit depth unknown
}

struct BadManifest {
  std::string text;
  std::string where;  // after "manifest.jsonl"
  std::string message;
};

TEST(RunFolderReader, BadManifestsNameTheLine) {
  const std::vector<BadManifest> cases = {
      {std::string(kDimLine) + "\n{\"index\":1,\"files\":{\"image\":\"x.png\"}", ":2:37", "invalid JSON"},
      {std::string(kDimLine) + "\n" + kDimLine + "\n", ":2", "frame 0 appears twice (first at "},
      {R"({"index":-1,"files":{"image":"x.png"}})", ":1: /index", "must be in [0, 1000000000], got -1"},
      {R"({"files":{"image":"x.png"}})", ":1: /", "missing required key \"index\""},
      {R"({"index":0,"files":{}})", ":1: /files", "missing required key \"image\""},
      {R"({"index":0,"files":{"image":""}})", ":1: /files/image", "must name the frame's image file"},
      {R"({"index":0,"files":{"image":"x.png"},"gt_axis":"diagonal"})", ":1: /gt_axis", "must be one of"},
      {R"({"index":0,"files":{"image":"x.png"},"bit_depth":17})", ":1: /bit_depth", "must be in [1, 16], got 17"},
      {R"({"index":0,"files":{"image":"x.png"},"png_bit_depth":12})", ":1: /png_bit_depth", "must be 8 or 16"},
      {R"({"index":0,"files":{"image":"x.png"},"world_from_cam":{"rotation_quat_wxyz":[1,1,0,0]}})",
       ":1: /world_from_cam/rotation_quat_wxyz", "unit norm"},
      {R"({"index":0,"files":{"image":"x.png"},"shutter":{"laser_on":"yes"}})", ":1: /shutter/laser_on",
       "must be true or false"},
      {"[1, 2]", ":1: /", "must be an object"},
  };
  int i = 0;
  for (const auto& c : cases) {
    fs::path run = NewRun("bad" + std::to_string(i++));
    Write(run / "manifest.jsonl", c.text);
    try {
      ReadRunManifest(run);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), StartsWith((run / "manifest.jsonl").string() + c.where)) << c.text;
      EXPECT_THAT(e.what(), HasSubstr(c.message)) << c.text;
    }
  }
}

TEST(RunFolderReader, MissingFolderOrManifest) {
  fs::path run = NewRun("empty");
  try {
    ReadRunManifest(run);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (run / "manifest.jsonl").string() + ": run manifest not found");
  }
  try {
    ReadRunManifest(run / "nowhere");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (run / "nowhere").string() + ": run folder not found");
  }
  try {
    ReadRunRig(run);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("holds neither rig.json nor scene.json"));
  }
}

// The sensor section of a scene with a distorted camera and a 3-sheet laser.
const char* kSensor = R"({
  "camera": {"resolution": [160, 120], "pixel_pitch_um": 19.2, "focal_length_mm": 8.889, "f_number": 5.6,
             "distortion": {"model": "brown_conrady", "k1": -0.2, "p1": 0.001}},
  "image_sensor": {"bit_depth": 12, "black_level_dn": 16},
  "lasers": [{"power_mw": 5, "wavelength_nm": 650, "sheet_count": 3, "sheet_spacing_deg": 2,
              "cam_from_projector": {"translation_m": [0, 0.04, 0], "rotation_rpy_deg": [26.565, 0, 0]}}]
})";

TEST(RunFolderReader, RigJsonAndSceneJsonGiveTheSameGeometry) {
  json::Document doc = json::Document::Parse(kSensor, "sensor", ".");
  SensorRig sensor = ParseSensorRig(doc.Root().AsObject());
  fs::path with_rig = NewRun("rig"), with_scene = NewRun("scene");
  Write(with_rig / "rig.json", SensorRigToJson(sensor).dump(2));
  Write(with_scene / "scene.json", std::string("{\"objects\": [], \"sensor\": ") + kSensor + "}");
  RunRig a = ReadRunRig(with_rig), b = ReadRunRig(with_scene);
  EXPECT_EQ(a.source, with_rig / "rig.json");
  EXPECT_EQ(b.source, with_scene / "scene.json");
  for (const RunRig* r : {&a, &b}) {
    EXPECT_EQ(r->camera.width(), 160);
    EXPECT_EQ(r->camera.distortion_model(), DistortionModel::kBrownConrady);
    EXPECT_EQ(r->camera.params().brown_conrady.p1, 0.001);
    EXPECT_EQ(r->bit_depth, 12);
    EXPECT_EQ(r->black_level_dn, 16);
    ASSERT_EQ(r->planes_in_cam.size(), 3u);
    for (int k = 0; k < 3; ++k) {
      const Plane truth = sensor.lasers[0].SheetPlane(k);
      EXPECT_EQ(r->planes_in_cam[size_t(k)].n, truth.n) << k;
      EXPECT_EQ(r->planes_in_cam[size_t(k)].d, truth.d) << k;
    }
    // What scan's colour weights need (pipeline/channel_weights.h); rig.json holds nm.
    ASSERT_EQ(r->laser_wavelength_m.size(), 1u);
    EXPECT_NEAR(r->laser_wavelength_m[0], 650e-9, 1e-21);
    const ImageSensorParams& sp = sensor.image_sensor.params();
    ASSERT_EQ(r->qe_wavelength_m.size(), sp.qe_wavelength_m.size());
    EXPECT_NEAR(r->qe_wavelength_m[0], sp.qe_wavelength_m[0], 1e-21);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(r->qe[size_t(c)], sp.qe[0]) << c;
    EXPECT_EQ(r->dark_noise_e, sp.dark_noise_e);
    EXPECT_EQ(r->system_gain_dn_per_e, sensor.image_sensor.SystemGain());
  }
  EXPECT_EQ(a.camera.fx(), b.camera.fx());
}

TEST(RunFolderReader, BadRigJson) {
  fs::path run = NewRun("badrig");
  Write(run / "rig.json", R"({"camera": {"resolution": [160, 120], "pixel_pitch_um": 5, "focal_length_mm": 4,
    "f_number": 4}, "lasers": [{"sheet_planes_in_cam": [{"n": [0, 2, 0], "d": 0.1}]}]})");
  try {
    ReadRunRig(run);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (run / "rig.json").string() +
                                         ": /lasers/0/sheet_planes_in_cam/0/n: must be a unit vector, got norm 2");
  }
  Write(run / "rig.json", R"({"camera": {"resolution": [160, 120], "pixel_pitch_um": 5, "focal_length_mm": 4,
    "f_number": 4}, "extra": 1})");
  EXPECT_THROW(ReadRunRig(run), InputError);
  Write(run / "rig.json", R"({"camera": {"resolution": [160, 120], "pixel_pitch_um": 5, "focal_length_mm": 4,
    "f_number": 4}, "image_sensor": {"color_filter": "rggb", "quantum_efficiency": {"wavelength_nm": [550, 650],
    "r": [0.5], "g": [0.5, 0.2], "b": [0.1, 0.05]}}})");
  try {
    ReadRunRig(run);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (run / "rig.json").string() +
                                         ": /image_sensor/quantum_efficiency/r: must have one value per wavelength (2), got 1");
  }
}

TEST(RunFolderReader, NoRigWarningSaysOnlyWhatIsAssumed) {
  NoRigAssumptions a;
  EXPECT_EQ(NoRigWarning("cap", a), "");
  a.mono = true;
  EXPECT_EQ(NoRigWarning("cap", a), "cap holds no rig.json: the image sensor is mono (--bayer sets a mosaic)");
  a.black_level_zero = true;
  a.camera_source = "cam.yaml";
  EXPECT_EQ(NoRigWarning("cap", a), "cap holds no rig.json: the camera is cam.yaml's, the image sensor's black level 0 "
                                    "(--background sets it), mono (--bayer sets a mosaic)");
  a.mono = false;
  a.bit_depth = "--bit-depth's";
  EXPECT_EQ(NoRigWarning("cap", a), "cap holds no rig.json: the camera is cam.yaml's, the image sensor's black level 0 "
                                    "(--background sets it), its bit depth --bit-depth's");
  a.black_level_zero = false;
  EXPECT_EQ(NoRigWarning("cap", a), "cap holds no rig.json: the camera is cam.yaml's, the image sensor's bit depth "
                                    "--bit-depth's");
  a = NoRigAssumptions{};
  a.camera_source = "cam.yaml";
  EXPECT_EQ(NoRigWarning("cap", a), "cap holds no rig.json: the camera is cam.yaml's");
}

}  // namespace
}  // namespace lt

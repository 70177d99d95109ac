// Scene files: the examples parse, defaults apply, paths resolve against the
// scene's folder, the resolved JSON is complete, and the loaded geometry places
// every object where its pose says.
#include "scene/scene_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "core/image_io.h"
#include "scene/embree_scene.h"
#include "scene/scene_geometry.h"
#include "test_util.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using test::ErrorOf;
using ::testing::HasSubstr;

const fs::path kScenes = fs::path(LT_SOURCE_DIR) / "tests/data/scenes";

TEST(SceneFile, MinimalSceneGetsTheDefaults) {
  SceneFile s = LoadSceneFile(kScenes / "minimal.json");
  EXPECT_EQ(s.seed, 1u);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].name, "square");
  EXPECT_TRUE(s.objects[0].world_from_object.matrix().isIdentity());
  EXPECT_EQ(s.objects[0].material, "");
  // The glTF path resolves against the scene file's folder, not the working folder.
  EXPECT_EQ(s.objects[0].gltf, (kScenes / "../gltf/square.gltf").lexically_normal());
  EXPECT_TRUE(s.materials.empty());
  EXPECT_EQ(s.environment.kind, Environment::Kind::kConstant);
  EXPECT_EQ(s.environment.radiance, Eigen::Vector3d::Zero());
  EXPECT_EQ(MotionTypeName(s.motion), "static");
  EXPECT_TRUE(WorldFromCamAt(s.motion, 3.0).matrix().isIdentity());
  EXPECT_EQ(s.render.spp, 16);
  EXPECT_EQ(s.render.max_bounces, 2);
  EXPECT_EQ(s.render.russian_roulette_depth, 3);
  EXPECT_TRUE(s.render.adaptive_sampling);
  EXPECT_EQ(s.render.adaptive_noise, 0.25);
  EXPECT_EQ(s.render.edge_spp_factor, 8);
  EXPECT_EQ(s.render.light_paths, 4096);
  EXPECT_TRUE(s.render.subsurface);
  EXPECT_TRUE(s.render.subsurface_cache);
  EXPECT_EQ(s.render.threads, 0);
  EXPECT_EQ(s.output.png_bit_depth, 8);
  EXPECT_TRUE(s.output.write_radiance);
  EXPECT_TRUE(s.output.write_ground_truth);
  EXPECT_EQ(s.sensor.camera.width(), 64);
  EXPECT_NO_THROW(s.render.Check());
  EXPECT_NO_THROW(s.output.Check());
  EXPECT_NO_THROW(s.environment.Check());
}

TEST(SceneFile, FullSceneValuesLandWhereTheyShould) {
  SceneFile s = LoadSceneFile(kScenes / "full.json");
  EXPECT_EQ(s.seed, 42u);
  ASSERT_EQ(s.objects.size(), 3u);
  EXPECT_EQ(s.objects[0].material, "painted");
  EXPECT_TRUE(s.objects[0].world_from_object.translation().isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_TRUE((s.objects[0].world_from_object.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  ASSERT_EQ(s.materials.size(), 2u);  // sorted by name
  EXPECT_EQ(s.materials[0].material.name, "lamp");
  EXPECT_EQ(s.materials[1].material.name, "painted");
  EXPECT_EQ(s.FindMaterial("painted"), 1);
  EXPECT_EQ(s.FindMaterial("nope"), -1);
  const Material& lamp = s.materials[0].material;
  EXPECT_TRUE(lamp.base_color.isApprox(Eigen::Vector3f::Constant(0.8f)));  // default
  EXPECT_EQ(lamp.roughness, 0.5f);
  EXPECT_TRUE(lamp.emissive.isApprox(Eigen::Vector3f(2, 2, 1.5)));
  ASSERT_TRUE(lamp.subsurface);
  EXPECT_TRUE(lamp.subsurface->mean_free_path_m.isApprox(Eigen::Vector3d(0.3e-3, 0.2e-3, 0.1e-3)));
  EXPECT_NEAR(lamp.subsurface->mean_free_path_laser_m, 0.3e-3, 1e-15);  // default: the red value
  const Material& painted = s.materials[1].material;
  EXPECT_FLOAT_EQ(painted.metallic, 0.1f);
  EXPECT_TRUE(painted.double_sided);
  EXPECT_NEAR(painted.subsurface->mean_free_path_laser_m, 0.5e-3, 1e-15);
  EXPECT_TRUE(painted.subsurface->mean_free_path_m.isApprox(Eigen::Vector3d::Constant(0.4e-3)));
  ASSERT_TRUE(painted.base_color_texture);
  EXPECT_EQ(painted.base_color_texture->image.width, 4);
  EXPECT_EQ(painted.base_color_texture->image.channels, 4);
  EXPECT_EQ(s.materials[1].base_color_texture_path, kScenes / "checker.png");
  EXPECT_NO_THROW(painted.Check());
  EXPECT_EQ(s.environment.kind, Environment::Kind::kMap);
  EXPECT_EQ(s.environment.exr, kScenes / "sky.exr");
  EXPECT_EQ(s.environment.scale, 2.5);
  EXPECT_TRUE(WorldFromCamAt(s.motion, 0).translation().isApprox(Eigen::Vector3d(0, 0, 0.1)));
  EXPECT_EQ(s.render.spp, 4);
  EXPECT_EQ(s.render.max_bounces, 0);
  EXPECT_EQ(s.render.russian_roulette_depth, 5);
  EXPECT_FALSE(s.render.adaptive_sampling);
  EXPECT_EQ(s.render.adaptive_noise, 0.5);
  EXPECT_EQ(s.render.edge_spp_factor, 3);
  EXPECT_EQ(s.render.light_paths, 100);
  EXPECT_FALSE(s.render.subsurface);
  EXPECT_FALSE(s.render.subsurface_cache);
  EXPECT_EQ(s.render.threads, 2);
  EXPECT_EQ(s.output.png_bit_depth, 16);
  EXPECT_FALSE(s.output.write_radiance);
  ASSERT_EQ(s.sensor.lasers.size(), 1u);
  EXPECT_DOUBLE_EQ(s.sensor.lasers[0].wavelength_m(), 450e-9);
}

TEST(SceneFile, ResolvedJsonHasAbsolutePathsAndDefaults) {
  test::TempDir other;
  const fs::path old = fs::current_path();
  fs::current_path(other.path());  // paths must not depend on the working folder
  SceneFile s = LoadSceneFile(kScenes / "minimal.json");
  SceneFile full = LoadSceneFile(kScenes / "full.json");
  fs::current_path(old);
  const nlohmann::json& r = s.resolved;
  EXPECT_EQ(r["objects"][0]["gltf"], (kScenes.parent_path() / "gltf/square.gltf").string());
  EXPECT_EQ(r["seed"], 1);
  EXPECT_EQ(r["render"]["spp"], 16);
  EXPECT_EQ(r["render"]["threads"], 0);
  EXPECT_EQ(r["output"]["png_bit_depth"], 8);
  EXPECT_EQ(r["motion"]["type"], "static");
  EXPECT_EQ(r["environment"]["radiance"], nlohmann::json({0.0, 0.0, 0.0}));
  EXPECT_EQ(r["sensor"], s.resolved["sensor"]);
  EXPECT_EQ(full.resolved["materials"]["painted"]["base_color_texture"], (kScenes / "checker.png").string());
  EXPECT_EQ(full.resolved["environment"]["exr"], (kScenes / "sky.exr").string());
  EXPECT_EQ(full.resolved["render"]["spp"], 4);  // given values are kept
  EXPECT_EQ(full.resolved["objects"][1]["scale"], 2.0);
  EXPECT_EQ(r["objects"][0]["scale"], 1.0);  // the default written out
  // The resolved scene is itself a valid scene that loads the same way, from anywhere.
  test::TempDir dir;
  test::WriteText(dir / "scene.json", full.resolved.dump());
  SceneFile again = LoadSceneFile(dir / "scene.json");
  EXPECT_EQ(again.objects[1].gltf, full.objects[1].gltf);
  EXPECT_EQ(again.resolved, full.resolved);
}

// Motions that read files (pose lists, G-code) keep working from the resolved scene.
TEST(SceneFile, ResolvedMotionFilesAreAbsolute) {
  const std::string head = R"({"objects": [{"name": "a", "gltf": "../gltf/square.gltf"}],
    "sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}},)";
  for (const std::string motion : {R"("motion": {"type": "pose_list", "file": "../poses/sweep.csv"}})",
                                   R"("motion": {"type": "gcode", "file": "../gcode/cura_square.gcode"}})"}) {
    SceneFile s = ParseSceneText(head + motion, "scene.json", kScenes);
    test::TempDir dir;
    test::WriteText(dir / "scene.json", s.resolved.dump());
    SceneFile again = LoadSceneFile(dir / "scene.json");
    EXPECT_EQ(MotionTypeName(again.motion), MotionTypeName(s.motion));
    for (double t : {0.0, 0.37, 1.5}) {
      EXPECT_TRUE(WorldFromCamAt(again.motion, t).isApprox(WorldFromCamAt(s.motion, t), 1e-12)) << motion << " " << t;
    }
  }
}

// A scene file written on Windows: backslashes as folder separators, names in
// another letter case. Its files are found as the glTF loader finds a uri's
// (core/file_lookup.h), and the resolved JSON names the files found.
TEST(SceneFile, PathsWrittenOnWindowsFindTheirFiles) {
  const std::string text = R"({"objects": [{"name": "a", "gltf": "..\\GLTF\\Square.gltf"}],
    "sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}},
    "motion": {"type": "pose_list", "file": "..\\poses\\SWEEP.csv"}})";
  const SceneFile s = ParseSceneText(text, "scene.json", kScenes);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].gltf, (kScenes / "../gltf/square.gltf").lexically_normal());
  EXPECT_EQ(fs::path(s.resolved["motion"]["file"].get<std::string>()),
            fs::absolute(kScenes / "../poses/sweep.csv").lexically_normal());
  EXPECT_THAT(ErrorOf([&] {
                ParseSceneText(R"({"objects": [{"name": "a", "gltf": "..\\gltf\\Circle.gltf"}], )" +
                                   std::string(R"("sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, )"
                                               R"("focal_length_mm": 4, "f_number": 4}}})"),
                               "scene.json", kScenes);
              }),
              HasSubstr("scene.json: /objects/0/gltf: glTF file not found (looked for "));
}

SceneFile Parse(const std::string& text) { return ParseSceneText(text, "scene.json", kScenes); }

const char* kSensor = R"("sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}})";

TEST(SceneFile, ErrorsNameTheFileAndPointer) {
  const std::string obj = R"("objects": [{"name": "a", "gltf": "../gltf/square.gltf"}], )";
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "seed": -2})"); }), "scene.json: /seed: must be >= 0, got -2");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + R"("sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 0}}})"); }),
            "scene.json: /sensor/camera/f_number: must be > 0, got 0");
  EXPECT_THAT(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "objects2": 1})"); }),
              HasSubstr("scene.json: /objects2: unknown key \"objects2\""));
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "render": {"spp": 2.5}})"); }),
            "scene.json: /render/spp: must be an integer, got 2.5");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "render": {"adaptive_noise": -0.1}})"); }),
            "scene.json: /render/adaptive_noise: must be in [0, 10], got -0.1");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "render": {"edge_spp_factor": 0}})"); }),
            "scene.json: /render/edge_spp_factor: must be in [1, 64], got 0");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "render": {"light_paths": 70000}})"); }),
            "scene.json: /render/light_paths: must be in [0, 65536], got 70000");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "materials": {"": {}}})"); }),
            "scene.json: /materials/: material names must not be empty");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "materials": {"m": {"subsurface": {"mean_free_path_mm": [1, 2]}}}})"); }),
            "scene.json: /materials/m/subsurface/mean_free_path_mm: must have 3 elements, got 2");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "materials": {"m": {"subsurface": {"mean_free_path_mm": "x"}}}})"); }),
            "scene.json: /materials/m/subsurface/mean_free_path_mm: must be a number or an array of 3 numbers (red, green, blue)");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "motion": {"world_from_cam": {}}})"); }),
            "scene.json: /motion: missing required key \"type\"");
  EXPECT_EQ(ErrorOf([&] { Parse(R"({"objects": [{"name": "", "gltf": "x.glb"}], )" + std::string(kSensor) + "}"); }),
            "scene.json: /objects/0/name: must not be empty");
  EXPECT_EQ(ErrorOf([&] {
              Parse(R"({"objects": [{"name": "a", "gltf": "../gltf/square.gltf", "scale": 0}], )" + std::string(kSensor) + "}");
            }),
            "scene.json: /objects/0/scale: must be > 0, got 0");
  // Files a scene names: missing, or not what the key needs.
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "environment": {"exr": "checker.png"}})"); }),
            "scene.json: /environment/exr: " + (kScenes / "checker.png").string() + " is not an OpenEXR file");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "environment": {"exr": "nope.exr"}})"); }),
            "scene.json: /environment/exr: environment map not found (looked for " + (kScenes / "nope.exr").string() + ")");
  EXPECT_EQ(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "motion": {"type": "pose_list", "file": "nope.csv"}})"); }),
            "scene.json: /motion/file: pose list not found (looked for " + (kScenes / "nope.csv").string() + ")");
  EXPECT_THAT(ErrorOf([&] { Parse("{" + obj + kSensor + R"(, "materials": {"m": {"base_color_texture": "minimal.json"}}})"); }),
              HasSubstr("scene.json: /materials/m/base_color_texture: " + (kScenes / "minimal.json").string() + ": cannot read image"));
}

TEST(SceneFile, MotionTypes) {
  EXPECT_EQ(MotionTypeNames(), (std::vector<std::string>{"gcode", "pose_list", "static"}));
  auto doc = json::Document::Parse(R"({"type": "static", "world_from_cam": {"translation_m": [1, 2, 3]}})", "m.json", ".");
  Motion m = ParseMotion(doc.Root());
  EXPECT_EQ(WorldFromCamAt(m, 0).translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(WorldFromCamAt(m, 100).translation(), Eigen::Vector3d(1, 2, 3));  // static: any time
  nlohmann::json j = MotionToJson(m);
  EXPECT_EQ(j["type"], "static");
  EXPECT_EQ(j["world_from_cam"]["translation_m"], nlohmann::json({1.0, 2.0, 3.0}));
}

// A camera straight above (or below) its target with no "up": the default up, +z,
// is parallel to the view, which was refused ("up is parallel to the view
// direction"). It is a plan view now, image top toward +y; an "up" given
// parallel to the view, or zero, is still an error naming it.
TEST(SceneFile, LookAtStraightDownWithoutUpIsAPlanView) {
  auto motion = [](const std::string& look_at) {
    return Parse("{" + std::string(R"("objects": [{"name": "a", "gltf": "../gltf/square.gltf"}], )") + kSensor +
                 R"(, "motion": {"type": "static", "world_from_cam": {"look_at": )" + look_at + "}}}")
        .motion;
  };
  Pose down = WorldFromCamAt(motion(R"({"eye_m": [0.1, 0.2, 1], "target_m": [0.1, 0.2, 0]})"), 0);
  EXPECT_TRUE(down.linear().isApprox((Eigen::Matrix3d() << 1, 0, 0, 0, -1, 0, 0, 0, -1).finished(), 1e-12))
      << down.linear();
  EXPECT_TRUE(down.translation().isApprox(Eigen::Vector3d(0.1, 0.2, 1)));
  Pose up = WorldFromCamAt(motion(R"({"eye_m": [0, 0, -1], "target_m": [0, 0, 0]})"), 0);
  EXPECT_TRUE(up.linear().col(2).isApprox(Eigen::Vector3d(0, 0, 1), 1e-12));
  EXPECT_TRUE(up.linear().col(1).isApprox(Eigen::Vector3d(0, -1, 0), 1e-12));  // image top toward +y
  EXPECT_NEAR(up.linear().determinant(), 1.0, 1e-12);
  // Off the vertical the default up is +z as before.
  Pose oblique = WorldFromCamAt(motion(R"({"eye_m": [1, 0, 1], "target_m": [0, 0, 0]})"), 0);
  EXPECT_LT(oblique.linear().col(1).z(), 0);  // image down = world down
  EXPECT_NEAR(oblique.linear().col(0).z(), 0, 1e-12);
  EXPECT_EQ(ErrorOf([&] { motion(R"({"eye_m": [0, 0, 1], "target_m": [0, 0, 0], "up": [0, 0, 2]})"); }),
            "scene.json: /motion/world_from_cam/look_at: up is parallel to the view direction");
  EXPECT_EQ(ErrorOf([&] { motion(R"({"eye_m": [0, 0, 1], "target_m": [1, 0, 0], "up": [0, 0, 0]})"); }),
            "scene.json: /motion/world_from_cam/look_at/up: must not be the zero vector");
  EXPECT_EQ(ErrorOf([&] { motion(R"({"eye_m": [0, 0, 1], "target_m": [0, 0, 1]})"); }),
            "scene.json: /motion/world_from_cam/look_at: eye and target coincide");
}

// A pose with look_at and another form's key: the other key was called unknown
// ('/motion/world_from_cam/translation_m: unknown key "translation_m" (known keys:
// look_at)'), though the docs' pose table lists it.
TEST(SceneFile, LookAtBesideAnotherPoseFormIsNamed) {
  auto pose = [](const std::string& world_from_cam) {
    std::string text = R"({"objects": [{"name": "a", "gltf": "../gltf/square.gltf"}], )";
    text += kSensor;
    text += R"(, "motion": {"type": "static", "world_from_cam": {)" + world_from_cam + "}}}";
    return Parse(text);
  };
  const std::string look = R"("look_at": {"eye_m": [0, 0, 1], "target_m": [0, 0, 0]})";
  EXPECT_EQ(ErrorOf([&] { pose(look + R"(, "translation_m": [0, 0, 1])"); }),
            "scene.json: /motion/world_from_cam/translation_m: look_at gives the whole pose (eye_m is the "
            "translation): give look_at or translation_m, not both");
  EXPECT_EQ(ErrorOf([&] { pose(R"("rotation_rpy_deg": [180, 0, 0], )" + look); }),
            "scene.json: /motion/world_from_cam/rotation_rpy_deg: look_at gives the whole pose (eye_m is the "
            "translation): give look_at or rotation_rpy_deg, not both");
  EXPECT_NO_THROW(pose(look));
}

// A folder given for the scene file (`lasertwin render scenes/demo`) was read as
// empty JSON: "scenes/demo:1:1: invalid JSON: ... unexpected end of input".
TEST(SceneFile, AFolderIsNotASceneFile) {
  EXPECT_EQ(ErrorOf([&] { LoadSceneFile(kScenes); }), kScenes.string() + ": is a folder, not a scene file");
  test::TempDir dir;
  test::WriteText(dir / "scene.json", "{}");
  EXPECT_EQ(ErrorOf([&] { LoadSceneFile(dir.path()); }),
            dir.path().string() + ": is a folder, not a scene file (it holds " + (dir / "scene.json").string() + ")");
}

// "objects": [] is a scene of nothing (dark frames, an environment-only flat
// field); it was refused ("must have at least 1 elements, got 0").
TEST(SceneFile, AnEmptySceneLoadsWithAWarning) {
  SceneFile s = Parse(R"({"objects": [], "environment": {"radiance": [0.1, 0.1, 0.1]}, )" + std::string(kSensor) + "}");
  EXPECT_TRUE(s.objects.empty());
  EXPECT_EQ(s.resolved["objects"], nlohmann::json::array());
  auto g = std::make_shared<const SceneGeometry>(LoadSceneGeometry(s));
  EXPECT_TRUE(g->instances.empty());
  EXPECT_THAT(g->warnings, ::testing::Contains(HasSubstr("the scene has no objects")));
  EmbreeScene scene(g);
  EXPECT_FALSE(scene.Intersect({{0, 0, 1}, {0, 0, -1}}));
  // The key itself is still required: a scene without it is more likely a mistake.
  EXPECT_EQ(ErrorOf([&] { Parse("{" + std::string(kSensor) + "}"); }), "scene.json: /: missing required key \"objects\"");
}

// A laser or LED 40 m from the camera is a baseline written in millimetres
// (40 for 0.04): the scene renders a stripe nowhere near the view, silently.
// An environment map was only read by the renderer: `info` called a truncated
// EXR valid, and a NaN, infinite or negative radiance went into the frames.
TEST(SceneFile, EnvironmentMapIsReadAndChecked) {
  test::TempDir dir;
  auto scene = [&](const fs::path& exr) {
    return Parse(R"({"objects": [], "environment": {"exr": ")" + exr.string() + R"("}, )" + std::string(kSensor) + "}");
  };
  Image<float> map(4, 2, 3, 0.5f);
  map.At(3, 1, 2) = 2.0f;
  WriteImage(dir / "good.exr", map);
  SceneFile good = scene(dir / "good.exr");
  ASSERT_TRUE(good.environment.map);
  EXPECT_EQ(good.environment.map->pixels, map.pixels);  // kept for the renderer: read once
  const std::string where = "scene.json: /environment/exr: ";
  for (float bad : {std::nanf(""), std::numeric_limits<float>::infinity(), -0.25f}) {
    Image<float> m = map;
    m.At(2, 1, 1) = bad;
    WriteImage(dir / "bad.exr", m);
    EXPECT_EQ(ErrorOf([&] { scene(dir / "bad.exr"); }),
              where + (dir / "bad.exr").string() + ": pixel (2, 1) channel 1 is " + FormatNumber(bad) +
                  "; an environment map holds radiance, finite and >= 0");
  }
  // A truncated file: its magic number is right, its pixels are missing.
  std::ifstream in(dir / "good.exr", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  test::WriteText(dir / "cut.exr", bytes.substr(0, bytes.size() / 2));
  EXPECT_THAT(ErrorOf([&] { scene(dir / "cut.exr"); }), ::testing::StartsWith(where + (dir / "cut.exr").string() + ": "));
}

TEST(SceneGeometry, EmittersFarFromTheCameraAreWarned) {
  const std::string head = R"({"objects": [{"name": "a", "gltf": "../gltf/square.gltf", "material": "m"}],
    "materials": {"m": {"base_color": [0.5, 0.5, 0.5]}},
    "sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4},)";
  auto warnings = [&](const std::string& laser_m, const std::string& led_m) {
    SceneFile s = Parse(head + R"("lasers": [{"power_mw": 5, "wavelength_nm": 650, "cam_from_projector": {"translation_m": )" +
                        laser_m + R"(}}], "led": {"size_m": [0.01, 0.01], "radiance_w_per_m2_sr": 100,
                        "cam_from_led": {"translation_m": )" + led_m + "}}}}");
    return LoadSceneGeometry(s).warnings;
  };
  EXPECT_THAT(warnings("[0, 0.04, 0]", "[0, -0.03, 0]"), ::testing::IsEmpty());
  EXPECT_THAT(warnings("[0, 1.5, 0]", "[0, -0.03, 0]"), ::testing::IsEmpty());  // a wide rig is no mistake
  EXPECT_THAT(warnings("[0, 40, 0]", "[0, -30, 0]"),
              ::testing::ElementsAre("sensor laser 0 is 40 m from the camera; its translation_m is in metres: if it is "
                                     "in millimetres, divide it by 1000",
                                     HasSubstr("sensor LED is 30 m from the camera")));
}

// A camera pitch, focal length or exposure written in the wrong unit (metres under
// pixel_pitch_um, metres under focal_length_mm, seconds under exposure_us) loaded
// without a word and rendered black frames.
TEST(SceneGeometry, CameraValuesInTheWrongUnitAreWarned) {
  auto warnings = [&](const std::string& pitch_um, const std::string& focal_mm, const std::string& exposure_us) {
    SceneFile s = Parse(R"({"objects": [{"name": "a", "gltf": "../gltf/square.gltf", "material": "m"}],
      "materials": {"m": {"base_color": [0.5, 0.5, 0.5]}},
      "sensor": {"camera": {"resolution": [64, 48], "f_number": 4, "pixel_pitch_um": )" + pitch_um +
                        R"(, "focal_length_mm": )" + focal_mm + R"(},
        "shutter": {"frame_period_ms": 10, "alternating": {"bright_exposure_us": 2000, "dim_exposure_us": )" +
                        exposure_us + "}}}}");
    return LoadSceneGeometry(s).warnings;
  };
  EXPECT_THAT(warnings("4.8", "8", "100"), ::testing::IsEmpty());
  EXPECT_THAT(warnings("0.56", "1.05", "1"), ::testing::IsEmpty());  // a phone's pixels, a fisheye, 1 us
  EXPECT_THAT(warnings("4.8e-6", "8", "100"),
              ::testing::ElementsAre("sensor camera pixel pitch is 4.8e-06 um; no sensor has pixels below 0.3 um: "
                                     "pixel_pitch_um is in micrometres (if it is in millimetres or metres, convert it)"));
  EXPECT_THAT(warnings("4.8", "0.008", "100"),
              ::testing::ElementsAre(HasSubstr("sensor camera focal length (fx times the pixel pitch) is 0.008 mm; no "
                                               "lens is shorter than 0.1 mm: focal_length_mm is in millimetres")));
  EXPECT_THAT(warnings("4.8", "8", "0.0001"),
              ::testing::ElementsAre("sensor shutter frame \"dim\" exposes for 0.0001 us; no camera exposes for less "
                                     "than 0.1 us: exposures are in microseconds (if it is in seconds, multiply it by "
                                     "1e6)"));
}

// square.gltf has no TEXCOORD_0: a scene material's base_color_texture on it was read
// at uv (0, 0) everywhere, the texture's corner colour, without a word.
TEST(SceneGeometry, ATextureOnAMeshWithoutTextureCoordinatesIsWarned) {
  auto warnings = [&](const std::string& material) {
    SceneFile s = Parse(R"({"objects": [{"name": "a", "gltf": "../gltf/square.gltf", "material": "m"}],
      "materials": {"m": )" + material + "}, " + kSensor + "}");
    return LoadSceneGeometry(s).warnings;
  };
  EXPECT_THAT(warnings(R"({"base_color": [0.5, 0.5, 0.5]})"), ::testing::IsEmpty());
  const auto w = warnings(R"({"base_color_texture": "checker.png"})");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_THAT(w[0], ::testing::StartsWith("object \"a\": "));
  EXPECT_THAT(w[0], ::testing::EndsWith("square.gltf has meshes without texture coordinates (TEXCOORD_0): the "
                                        "base_color_texture of material \"m\" is read at uv (0, 0) all over them, "
                                        "one colour"));
}

TEST(SceneGeometry, AFileThatCannotBeReadNamesTheObjectThatGaveIt) {
  // The loader's message names the glTF file (and its place in it); a scene of
  // many objects also needs which object, at which key, gave that file.
  const fs::path dir = fs::path(::testing::TempDir()) / "lt_scene_bad_gltf";
  fs::create_directories(dir);
  std::ofstream(dir / "notes.gltf") << "hello";
  SceneFile s = Parse(R"({"objects": [{"name": "a", "gltf": "../gltf/square.gltf"},
    {"name": "part", "gltf": ")" + (dir / "notes.gltf").string() + R"("}], )" + kSensor + "}");
  const std::string e = ErrorOf([&] { LoadSceneGeometry(s); });
  EXPECT_THAT(e, HasSubstr("notes.gltf: neither a GLB"));
  EXPECT_THAT(e, ::testing::EndsWith(" (object \"part\", /objects/1/gltf of scene.json)"));

  // A file whose materials refuse it is read with them for the object that takes them:
  // that object is named, in either order, not one with its own material.
  std::ofstream(dir / "shader.gltf")
      << R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_techniques_webgl"],
             "extensionsRequired": ["KHR_techniques_webgl"]})";
  const std::string shader = (dir / "shader.gltf").string();
  const std::string own = R"({"name": "own", "gltf": ")" + shader + R"(", "material": "m"})";
  const std::string takes = R"({"name": "takes", "gltf": ")" + shader + R"("})";
  for (const bool own_first : {true, false}) {
    SceneFile both = Parse(R"({"objects": [)" + (own_first ? own + ", " + takes : takes + ", " + own) +
                           R"(], "materials": {"m": {"base_color": [0.5, 0.5, 0.5]}}, )" + kSensor + "}");
    EXPECT_THAT(ErrorOf([&] { LoadSceneGeometry(both); }),
                ::testing::EndsWith(" (object \"takes\", /objects/" + std::string(own_first ? "1" : "0") +
                                    "/gltf of scene.json)"));
  }
}

TEST(SceneGeometry, ObjectsShareTheirGltfAndKeepTheirPoses) {
  SceneFile s = LoadSceneFile(kScenes / "full.json");
  auto g = std::make_shared<const SceneGeometry>(LoadSceneGeometry(s));
  // Three objects use square.gltf: loaded once.
  ASSERT_EQ(g->meshes.size(), 1u);
  ASSERT_EQ(g->instances.size(), 3u);
  EXPECT_EQ(g->object_names, (std::vector<std::string>{"tile", "tile_glowing", "tile_plain"}));
  EXPECT_EQ(g->instances[0].name, "tile/square");
  // Scene materials first (lamp, painted), then the file's default material.
  ASSERT_EQ(g->materials.size(), 3u);
  EXPECT_EQ(g->materials[2].name, "default");
  EXPECT_EQ(g->instances[0].material_override, 1);
  EXPECT_EQ(g->instances[1].material_override, 0);
  EXPECT_EQ(g->instances[2].material_override, -1);
  EXPECT_EQ(g->MaterialOf(g->instances[2], 0), 2u);
  // Only the object without a material of its own is told it renders as metal.
  std::vector<std::string> default_warnings;
  for (const std::string& w : g->warnings) {
    if (w.find("without a material") != std::string::npos) default_warnings.push_back(w);
  }
  ASSERT_EQ(default_warnings.size(), 1u);
  EXPECT_THAT(default_warnings[0], HasSubstr("object \"tile_plain\": "));
  EXPECT_THAT(default_warnings[0], HasSubstr("take glTF's default: white metal of roughness 1"));
  EXPECT_EQ(g->UniqueTriangleCount(), 2u);
  EXPECT_EQ(g->InstancedTriangleCount(), 6u);
  // square.gltf is a unit square scaled to 10 mm by its node; "tile" is turned
  // 90 deg about z and moved 0.1 m along x, so mesh corner (1, 0, 0) is at
  // (0.1, 0.01, 0).
  EXPECT_TRUE((g->instances[0].world_from_mesh * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(0.1, 0.01, 0)));
  // "tile_glowing" is scaled by 2 before its pose moves it 0.01 m down.
  EXPECT_TRUE((g->instances[1].world_from_mesh * Eigen::Vector3d(1, 1, 0)).isApprox(Eigen::Vector3d(0.02, 0.02, -0.01)));
  // A ray down onto the turned tile hits it, with the painted material.
  EmbreeScene scene(g);
  auto hit = scene.Intersect({{0.095, 0.005, 1}, {0, 0, -1}});
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->instance_id, 0u);
  EXPECT_EQ(hit->material_id, 1u);
  EXPECT_LT((hit->position - Eigen::Vector3d(0.095, 0.005, 0)).norm(), 1e-15) << hit->position.transpose();
  auto lower = scene.Intersect({{0.005, 0.005, -0.005}, {0, 0, -1}});
  ASSERT_TRUE(lower);
  EXPECT_EQ(lower->material_id, 0u);  // lamp
  EXPECT_NEAR(lower->position.z(), -0.01, 1e-9);
}

}  // namespace
}  // namespace lt

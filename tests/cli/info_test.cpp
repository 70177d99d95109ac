// `lasertwin info` end to end: the example scenes load (exit 0) and each bad
// scene file in tests/data/scenes/bad gives its message on stderr, naming the
// file and the JSON pointer, with exit code 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_util.h"
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <future>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <set>
#include <string>

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

const fs::path kSource = LT_SOURCE_DIR;
const fs::path kData = kSource / "tests" / "data";

using Result = lt::test::CliResult;
using lt::test::Quoted;
using lt::test::ReadFile;

Result RunLasertwin(const std::string& args) { return lt::test::RunCli(args); }

TEST(InfoCommand, DemoSceneLoads) {
  Result r = RunLasertwin("info --json " + Quoted(kSource / "scenes/demo/scene.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["objects"].size(), 2u);
  EXPECT_EQ(j["objects"][0]["name"], "test_part");
  EXPECT_EQ(j["objects"][0]["material"], "pla_white");
  EXPECT_EQ(j["geometry"]["instances"], 2);
  EXPECT_EQ(j["geometry"]["degenerate_triangles_dropped"], 0);
  // The print bed (150 x 150 mm, top at z = 0, 2 mm thick) bounds the scene; the
  // 3 mm part stands on it.
  // 1e-8: the vertices are stored as float (0.075 m is 0.0750000030 as a float).
  EXPECT_NEAR(j["bounds_m"]["min"][0].get<double>(), -0.075, 1e-8);
  EXPECT_NEAR(j["bounds_m"]["max"][1].get<double>(), 0.075, 1e-8);
  EXPECT_NEAR(j["bounds_m"]["min"][2].get<double>(), -0.002, 1e-8);
  EXPECT_NEAR(j["bounds_m"]["max"][2].get<double>(), 0.003, 1e-8);
  EXPECT_EQ(j["sensor"]["camera"]["resolution"], nlohmann::json({1280, 1024}));
  EXPECT_EQ(j["sensor"]["lasers"][0]["wavelength_nm"].get<double>(), 650.0);
  EXPECT_EQ(j["warnings"].size(), 0u);
}

// The horizontal field of view includes the lens distortion: the test scene's
// barrel distortion (k1 = -0.2, k2 = 0.05) sees more than its pinhole would.
// Closed form on the principal row: the edge's distorted normalised coordinate
// x_d = (width / 2) / fx is x_u (1 + k1 x_u^2 + k2 x_u^4), solved by fixed-point
// iteration; the tangential terms (p1, p2 ~ 1e-3) move both edges the same
// way and change the angle between them by well under 0.001 deg.
TEST(InfoCommand, FieldOfViewIncludesDistortion) {
  Result r = RunLasertwin("info --json " + Quoted(kData / "scenes/scan_distorted.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto cam = nlohmann::json::parse(r.out)["sensor"]["camera"];
  const double x_d = 0.5 * cam["resolution"][0].get<double>() / cam["fx"].get<double>();
  double x_u = x_d;
  for (int i = 0; i < 50; ++i) x_u = x_d / (1 - 0.2 * x_u * x_u + 0.05 * x_u * x_u * x_u * x_u);
  const double expected = 2 * std::atan(x_u) * 180 / M_PI, pinhole = 2 * std::atan(x_d) * 180 / M_PI;
  EXPECT_NEAR(cam["horizontal_fov_deg"].get<double>(), expected, 0.002);
  EXPECT_GT(expected - pinhole, 0.05);
}

TEST(InfoCommand, TextOutputNamesEverySection) {
  Result r = RunLasertwin("info " + Quoted(kData / "scenes/full.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* s : {"objects: 3", "geometry: 6 triangles (2 unique in 1 meshes), 3 instances",
                        "bounds (world, mm): min [0, 0, -10] max [100, 20, 0]", "materials: 3", "1 painted:",
                        "texture ", "checker.png (4x4)", "emissive [2, 2, 1.5] W/(m^2 sr)",
                        "laser 0: 450 nm, 5 mW", "motion: static, camera at [0, 0, 100] mm looking along [0, 0, -1]",
                        "\"scale\":2.5", "\"spp\":4", "\"png_bit_depth\":16",
                        "warnings: 2\n  object \"tile\": ", "the base_color_texture of material \"painted\" is read at uv (0, 0)",
                        "\n  object \"tile_plain\": "}) {
    EXPECT_THAT(r.out, HasSubstr(s));
  }
}

// A glTF's alpha modes (glTF 3.9.4) and double-sidedness, as the renderer reads
// them: the same square under three meshes, one material each.
TEST(InfoCommand, TextAndJsonNameAlphaModes) {
  const fs::path dir = lt::test::TestFolder("info_alpha");
  fs::create_directories(dir);
  nlohmann::json g = nlohmann::json::parse(ReadFile(kData / "gltf/square.gltf"));
  g["materials"] = {{{"name", "opaque"}},
                    {{"name", "stencil"}, {"alphaMode", "MASK"}, {"alphaCutoff", 0.3}, {"doubleSided", true},
                     {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.9}}}}},
                    {{"name", "glass"}, {"alphaMode", "BLEND"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.4}}}}}};
  const nlohmann::json primitive = g["meshes"][0]["primitives"][0];
  g["meshes"] = nlohmann::json::array();
  g["nodes"] = nlohmann::json::array();
  g["scenes"][0]["nodes"] = nlohmann::json::array();
  for (int m = 0; m < 3; ++m) {
    nlohmann::json prim = primitive;
    prim["material"] = m;
    g["meshes"].push_back({{"primitives", {prim}}});
    g["nodes"].push_back({{"mesh", m}, {"translation", {0.02 * m, 0, 0}}, {"scale", {0.01, 0.01, 0.01}}});
    g["scenes"][0]["nodes"].push_back(m);
  }
  std::ofstream(dir / "plates.gltf") << g.dump();
  std::ofstream(dir / "scene.json") << R"({"objects": [{"name": "plates", "gltf": "plates.gltf"}],
    "sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}}})";
  Result r = RunLasertwin("info " + Quoted(dir / "scene.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("0 opaque: base_color [1, 1, 1], metallic 1, roughness 1\n"));
  EXPECT_THAT(r.out, HasSubstr(", double-sided, alpha mask (holes where alpha < 0.3, alpha 0.9)\n"));
  EXPECT_THAT(r.out, HasSubstr(", alpha blend (alpha 0.4 read as coverage)\n"));
  Result j = RunLasertwin("info --json " + Quoted(dir / "scene.json"));
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto materials = nlohmann::json::parse(j.out)["materials"];
  ASSERT_EQ(materials.size(), 3u);
  EXPECT_FALSE(materials[0].contains("alpha_mode"));
  EXPECT_EQ(materials[1]["alpha_mode"], "mask");
  EXPECT_NEAR(materials[1]["alpha_cutoff"].get<double>(), 0.3, 1e-6);
  EXPECT_EQ(materials[1]["double_sided"], true);
  EXPECT_EQ(materials[2]["alpha_mode"], "blend");
  EXPECT_NEAR(materials[2]["alpha"].get<double>(), 0.4, 1e-6);
  EXPECT_FALSE(materials[2].contains("alpha_cutoff"));
  fs::remove_all(dir);
}

// Materials no triangle takes are marked, so that a change to one having no effect
// is explained: a glTF material library's extra material and a scene material no
// object takes. Before, both were listed as the used ones are.
TEST(InfoCommand, MarksMaterialsNoTriangleTakes) {
  const fs::path dir = lt::test::TestFolder("info_unused");
  fs::create_directories(dir);
  nlohmann::json g = nlohmann::json::parse(ReadFile(kData / "gltf/square.gltf"));
  g["materials"] = {{{"name", "grey"}, {"pbrMetallicRoughness", {{"metallicFactor", 0}}}},
                    {{"name", "oak"}, {"pbrMetallicRoughness", {{"metallicFactor", 0}}}}};
  g["meshes"][0]["primitives"][0]["material"] = 0;
  std::ofstream(dir / "library.gltf") << g.dump();
  std::ofstream(dir / "scene.json") << R"({"objects": [{"name": "plate", "gltf": "library.gltf"}],
    "materials": {"pla": {"base_color": [0.8, 0.8, 0.8]}},
    "sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}}})";
  Result r = RunLasertwin("info " + Quoted(dir / "scene.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("materials: 3 (2 unused)\n"));
  EXPECT_THAT(r.out, HasSubstr("  0 pla: base_color [0.8, 0.8, 0.8], metallic 0, roughness 0.5; unused: no object takes it\n"));
  EXPECT_THAT(r.out, HasSubstr("  1 grey: base_color [1, 1, 1], metallic 0, roughness 1\n"));
  EXPECT_THAT(r.out, HasSubstr("  2 oak: base_color [1, 1, 1], metallic 0, roughness 1; unused: no triangle the scene "
                               "places uses it\n"));
  Result j = RunLasertwin("info --json " + Quoted(dir / "scene.json"));
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto materials = nlohmann::json::parse(j.out)["materials"];
  ASSERT_EQ(materials.size(), 3u);
  EXPECT_EQ(materials[0]["unused"], "no object takes it");
  EXPECT_FALSE(materials[1].contains("unused"));
  EXPECT_EQ(materials[2]["unused"], "no triangle the scene places uses it");
  fs::remove_all(dir);
}

TEST(InfoCommand, ListsWarnings) {
  // warnings.gltf: a triangle, a collinear (degenerate) triangle and a points primitive.
  Result r = RunLasertwin("info " + Quoted(kData / "scenes/warnings.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string gltf = (kData / "gltf/warnings.gltf").string();
  EXPECT_THAT(r.out, HasSubstr("geometry: 1 triangles (1 unique in 1 meshes), 1 instances, 1 degenerate triangles dropped"));
  EXPECT_THAT(r.out, HasSubstr("warnings: 3\n  " + gltf +
                               ": mesh \"bracket\" primitive 1: points skipped (only triangles are rendered)\n  " + gltf +
                               ": 1 degenerate triangles dropped\n  object \"bracket\": " + gltf +
                               " has primitives without a material"));
}

TEST(InfoCommand, MissingSceneFile) {
  const fs::path p = kData / "scenes/does_not_exist.json";
  Result r = RunLasertwin("info " + Quoted(p));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_THAT(r.err, HasSubstr(p.string() + ": cannot open file (looked for " + p.string() + ")"));
}

TEST(InfoCommand, UsageErrorsExitWithTwo) {
  EXPECT_EQ(RunLasertwin("info").exit_code, 2);
  EXPECT_EQ(RunLasertwin("info --no-such-flag x.json").exit_code, 2);
}

struct BadScene {
  const char* file;      // in tests/data/scenes/bad
  std::string message;   // what follows "lasertwin: error: <where>"
  bool gltf = false;     // the error names a glTF file first, then the scene's object "square" that gave it
};

// {file, expected message}. For scene errors the message follows
// "<scene path>: "; for glTF errors it is complete after "lasertwin: error: ".
std::vector<BadScene> BadScenes() {
  const std::string bad = (kData / "scenes/bad").string();
  const std::string gltf = (kData / "gltf").string();
  return {
      {"unknown_top_key.json",
       "/seeds: unknown key \"seeds\" (known keys: $schema, description, environment, materials, motion, objects, "
       "output, print, render, seed, sensor)"},
      {"seed_negative.json", "/seed: must be >= 0, got -1"},
      {"seed_not_integer.json", "/seed: must be an integer, got 1.5"},
      {"objects_missing.json", "/: missing required key \"objects\""},
      {"object_unknown_key.json",
       "/objects/0/colour: unknown key \"colour\" (known keys: gltf, material, name, scale, world_from_object)"},
      {"object_gltf_missing.json",
       "/objects/0/gltf: glTF file not found (looked for " + bad + "/nowhere/part.glb)"},
      {"object_duplicate_name.json", "/objects/1/name: duplicate object name \"square\""},
      {"object_unknown_material.json", "/objects/0/material: unknown material \"steel\" (known: \"pla\")"},
      {"object_bad_pose.json",
       "/objects/0/world_from_object/rotation_quat_wxyz: rotation quaternion must have unit norm, got norm "
       "1.4142135623730951"},
      {"material_base_color_range.json", "/materials/pla/base_color/0: must be in [0, 1], got 1.2"},
      {"material_roughness_type.json", "/materials/pla/roughness: must be a number, got a string"},
      {"material_subsurface_zero.json", "/materials/pla/subsurface/mean_free_path_mm: must be > 0, got 0"},
      {"material_texture_missing.json",
       "/materials/pla/base_color_texture: texture not found (looked for " + bad + "/wood.png)"},
      {"environment_both.json", "/environment: give exactly one of \"radiance\" (constant) or \"exr\" (map)"},
      {"environment_negative.json", "/environment/radiance/1: must be >= 0, got -0.5"},
      {"environment_exr_missing.json",
       "/environment/exr: environment map not found (looked for " + (kData / "scenes/missing_sky.exr").string() + ")"},
      {"sensor_missing.json", "/: missing required key \"sensor\""},
      {"camera_f_number_zero.json", "/sensor/camera/f_number: must be > 0, got 0"},
      {"camera_resolution_zero.json", "/sensor/camera/resolution/0: must be in [1, 65536], got 0"},
      {"shutter_negative_exposure.json", "/sensor/shutter/alternating/dim_exposure_us: must be > 0, got -0.5"},
      {"laser_power_negative.json", "/sensor/lasers/0/power_mw: must be > 0, got -5"},
      {"motion_unknown_type.json", "/motion/type: must be one of \"gcode\", \"pose_list\", \"static\", got \"robot\""},
      {"motion_unknown_key.json",
       "/motion/world_from_camera: unknown key \"world_from_camera\" (known keys: type, world_from_cam)"},
      {"render_spp_zero.json", "/render/spp: must be in [1, 65536], got 0"},
      {"print_chunk_moves_zero.json", "/print/chunk_moves: must be in [1, 1000000000], got 0"},
      {"render_threads_negative.json", "/render/threads: must be in [0, 1024], got -1"},
      {"output_bit_depth.json", "/output/png_bit_depth: must be 8 or 16, got 12"},
      {"output_bool_type.json", "/output/write_radiance: must be true or false, got a string"},
      {"gltf_truncated.json", gltf + "/truncated.glb: invalid GLB: truncated: the header says 832 bytes, the file has 416",
       true},
      {"gltf_index_past_vertex_count.json",
       gltf + "/bad_index.gltf: /accessors/2: index 7 (element 5) is past the vertex count 4", true},
      {"gltf_nan_position.json", gltf + "/nan_position.gltf: /accessors/0: position 2 is not finite (nan)", true},
      {"gltf_missing_buffer.json",
       gltf + "/missing_buffer.gltf: /buffers/0/uri: buffer file not found (looked for " + gltf + "/missing_buffer.bin)",
       true},
      {"gltf_view_out_of_range.json",
       gltf + "/view_out_of_range.gltf: /bufferViews/0: byte range [4096, 4144) is outside buffer 0 (120 bytes)", true},
  };
}

TEST(InfoCommand, BadScenesGiveTheirMessageAndExitCodeTwo) {
  auto cases = BadScenes();
  ASSERT_GE(cases.size(), 20u);
  // The runs are independent processes: start them a few at a time.
  std::vector<std::future<Result>> runs;
  for (const BadScene& c : cases) {
    const fs::path p = kData / "scenes/bad" / c.file;
    ASSERT_TRUE(fs::exists(p)) << p;
    runs.push_back(std::async(std::launch::async, [p] { return RunLasertwin("info " + Quoted(p)); }));
    if (runs.size() % 4 == 0) runs[runs.size() - 4].wait();
  }
  for (size_t i = 0; i < cases.size(); ++i) {
    const BadScene& c = cases[i];
    const fs::path p = kData / "scenes/bad" / c.file;
    Result r = runs[i].get();
    EXPECT_EQ(r.exit_code, 2) << c.file;
    EXPECT_EQ(r.out, "") << c.file;
    const std::string expected =
        "lasertwin: error: " +
        (c.gltf ? c.message + " (object \"square\", /objects/0/gltf of " + p.string() + ")" : p.string() + ": " + c.message) +
        "\n";
    EXPECT_EQ(r.err, expected) << c.file;
  }
}

// JSON that is not even JSON (NaN, a trailing comma) names file:line:column.
TEST(InfoCommand, SyntaxErrorsNameLineAndColumn) {
  for (auto [file, place] : {std::pair{"nan_value.json", ":3:21: invalid JSON: "},
                             std::pair{"trailing_comma.json", ":2:68: invalid JSON: "}}) {
    const fs::path p = kData / "scenes/bad" / file;
    Result r = RunLasertwin("info " + Quoted(p));
    EXPECT_EQ(r.exit_code, 2) << file;
    EXPECT_THAT(r.err, StartsWith("lasertwin: error: " + p.string() + place)) << file;
  }
}

// Every file in the bad folder is covered by one of the tests above.
TEST(InfoCommand, EveryBadSceneIsChecked) {
  std::set<std::string> listed = {"nan_value.json", "trailing_comma.json"};
  for (const auto& c : BadScenes()) listed.insert(c.file);
  for (const auto& entry : fs::directory_iterator(kData / "scenes/bad")) {
    EXPECT_TRUE(listed.count(entry.path().filename().string())) << entry.path();
  }
}

}  // namespace

// docs/scene.schema.json: a valid Draft 2020-12 schema that the example scenes
// satisfy and that rejects what the parser rejects where a schema can tell
// (types, ranges, unknown keys, required keys). Runs python3's jsonschema.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_util.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kSource = LT_SOURCE_DIR;

// Checks the schema, then validates each file; prints "file: /pointer: message"
// per error and exits 1 when any file has errors.
const char* kValidate = R"(
import json, sys, jsonschema
schema = json.load(open(sys.argv[1]))
jsonschema.Draft202012Validator.check_schema(schema)
validator = jsonschema.Draft202012Validator(schema)
bad = 0
for name in sys.argv[2:]:
    errors = list(validator.iter_errors(json.load(open(name))))
    for e in errors:
        print(name + ": /" + "/".join(str(p) for p in e.absolute_path) + ": " + e.message)
    bad += bool(errors)
sys.exit(1 if bad else 0)
)";

struct Result {
  int exit_code;
  std::string output;
};

Result Validate(const std::vector<fs::path>& files) {
  test::TempDir dir;
  std::string command = std::string(LT_PYTHON3) + " -c '" + kValidate + "' '" +
                        (kSource / "docs/scene.schema.json").string() + "'";
  for (const auto& f : files) command += " '" + f.string() + "'";
  command += " >" + (dir / "out.txt").string() + " 2>&1";
  int status = std::system(command.c_str());
  std::ifstream in(dir / "out.txt");
  std::stringstream ss;
  ss << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
}

TEST(SceneSchema, ExamplesValidate) {
  Result r = Validate({kSource / "scenes/demo/scene.json", kSource / "scenes/print/scene.json", kSource / "tests/data/scenes/minimal.json",
                       kSource / "tests/data/scenes/full.json", kSource / "tests/data/scenes/warnings.json"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "");
}

// Bad scenes whose fault a schema can see, and the pointer it must name.
TEST(SceneSchema, RejectsWhatTheParserRejects) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"unknown_top_key", ": /: Additional properties are not allowed ('seeds' was unexpected)"},
      {"seed_negative", ": /seed: -1 is less than the minimum of 0"},
      {"seed_not_integer", ": /seed: 1.5 is not of type 'integer'"},
      {"objects_missing", ": /: 'objects' is a required property"},
      {"object_unknown_key", ": /objects/0: Additional properties are not allowed ('colour' was unexpected)"},
      {"material_base_color_range", ": /materials/pla/base_color/0: 1.2 is greater than the maximum of 1"},
      {"material_roughness_type", ": /materials/pla/roughness: 'rough' is not of type 'number'"},
      {"material_subsurface_zero", ": /materials/pla/subsurface/mean_free_path_mm: "},
      {"environment_both", ": /environment: "},
      {"environment_negative", ": /environment: "},
      {"sensor_missing", ": /: 'sensor' is a required property"},
      {"camera_f_number_zero", ": /sensor/camera/f_number: 0 is less than or equal to the minimum of 0"},
      {"camera_resolution_zero", ": /sensor/camera/resolution/0: 0 is less than the minimum of 1"},
      {"laser_power_negative", ": /sensor/lasers/0/power_mw: -5 is less than or equal to the minimum of 0"},
      {"motion_unknown_type", ": /motion/type: 'robot' is not one of ['static', 'pose_list', 'gcode']"},
      {"motion_unknown_key", ": /motion: "},
      {"render_spp_zero", ": /render/spp: 0 is less than the minimum of 1"},
      {"render_threads_negative", ": /render/threads: -1 is less than the minimum of 0"},
      {"output_bit_depth", ": /output/png_bit_depth: 12 is not one of [8, 16]"},
      {"output_bool_type", ": /output/write_radiance: 'yes' is not of type 'boolean'"},
      {"print_chunk_moves_zero", ": /print/chunk_moves: 0 is less than the minimum of 1"},
  };
  std::vector<fs::path> files;
  for (const auto& [name, message] : cases) files.push_back(kSource / "tests/data/scenes/bad" / (name + ".json"));
  Result r = Validate(files);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  for (size_t i = 0; i < cases.size(); ++i) {
    EXPECT_THAT(r.output, HasSubstr(files[i].string() + cases[i].second)) << cases[i].first;
  }
}

}  // namespace
}  // namespace lt

// Scenes written from docs/scene-format.md alone, rendered by `lasertwin render`:
// the ground truth of features in combinations the bundled scenes do not use lies
// where the page's closed forms put it (docs/scene-format.md, "Checked scenes").
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_util.h"
#include "plane_scene.h"

namespace lt::test {
namespace {

namespace fs = std::filesystem;

struct Centre {
  double u, v, z_world;
  int plane;
};

// Renders `scene` and returns frame 0's ground-truth centres and its manifest line.
std::vector<Centre> RenderCentres(const std::string& name, const nlohmann::json& scene, nlohmann::json* manifest) {
  const fs::path dir = TestFolder(name);
  fs::create_directories(dir);
  std::ofstream(dir / "scene.json") << scene.dump();
  const CliResult r = RunCli("render " + Quoted(dir / "scene.json") + " --out " + Quoted(dir / "run") + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return {};
  std::istringstream lines(ReadFile(dir / "run/manifest.jsonl"));
  std::string line;
  std::getline(lines, line);
  *manifest = nlohmann::json::parse(line);
  std::vector<Centre> centres;
  std::istringstream csv(ReadFile(dir / "run/gt/000000_centers.csv"));
  std::getline(csv, line);  // u,v,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world
  while (std::getline(csv, line)) {
    std::vector<double> f;
    std::stringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(std::stod(x));
    centres.push_back({f[0], f[1], f[8], int(f[2])});
  }
  fs::remove_all(dir);
  return centres;
}

// A diffractive element written with sheet_angles_deg: sheet k's central ray is
// (0, sin a_k, cos a_k) in the projector frame, so after the projector's tilt by
// roll t about x it meets the plane at y_cam = 0.04 - 0.1 tan(t - a_k); the sheets
// are numbered in the order of their angles; the stripes run along the rows, so
// the centres are per column (gt_axis "cols"), in every column.
TEST(SceneFeatures, DiffractiveSheetsLieWhereTheirAnglesSay) {
  const double tilt = std::atan(0.4);
  const nlohmann::json laser = {{"power_mw", 3}, {"wavelength_nm", 650}, {"divergence_deg", 1},
                                {"sheet_angles_deg", {-8, -1, 6}},
                                {"cam_from_projector",
                                 {{"translation_m", {0, 0.04, 0}}, {"rotation_rpy_deg", {tilt * 180 / M_PI, 0, 0}}}}};
  nlohmann::json manifest;
  const auto centres = RenderCentres("scene_features_doe", PlaneScene(nlohmann::json::array({laser})), &manifest);
  EXPECT_EQ(manifest["gt_axis"], "cols");
  ASSERT_EQ(centres.size(), 3u * 64u);
  const double angles[3] = {-8, -1, 6};
  std::vector<int> per_plane(3, 0);
  for (const Centre& c : centres) {
    ASSERT_TRUE(c.plane >= 0 && c.plane < 3) << c.plane;
    ++per_plane[size_t(c.plane)];
    const double y_cam = 0.04 - 0.1 * std::tan(tilt - angles[c.plane] * M_PI / 180);
    EXPECT_NEAR(c.v, 23.5 + 88 * y_cam / 0.1, 1e-5) << "u " << c.u << " plane " << c.plane;
    EXPECT_NEAR(c.z_world, 0, 1e-9);
  }
  EXPECT_EQ(per_plane, (std::vector<int>{64, 64, 64}));
}

// A sheet turned by a rotation_matrix so that the fan opens along the camera's y
// (baseline along x): the stripe runs down the image, the centres are per row
// (gt_axis "rows") at u = cx, where the sheet meets the plane on the optical axis.
TEST(SceneFeatures, AVerticalStripeHasCentresPerRow) {
  const double c = 1 / std::sqrt(1.16), s = 0.4 / std::sqrt(1.16);  // tilt atan(0.4) toward -x
  const nlohmann::json laser = {
      {"power_mw", 2}, {"wavelength_nm", 650}, {"divergence_deg", 1},
      {"cam_from_projector",
       {{"translation_m", {0.04, 0, 0}}, {"rotation_matrix", {{0, -c, -s}, {1, 0, 0}, {0, -s, c}}}}}};
  nlohmann::json manifest;
  const auto centres = RenderCentres("scene_features_vertical", PlaneScene(nlohmann::json::array({laser})), &manifest);
  EXPECT_EQ(manifest["gt_axis"], "rows");
  ASSERT_EQ(centres.size(), 48u);
  for (size_t i = 0; i < centres.size(); ++i) {
    EXPECT_EQ(centres[i].v, double(i));
    EXPECT_NEAR(centres[i].u, 31.5, 1e-5);
  }
}

}  // namespace
}  // namespace lt::test

// Rendering a scene whose printed part grows (scene key "print"): the frame shows
// the beads laid down by its mid-exposure time, the ground truth (instance ids,
// exact stripe centres) includes them, and the frame reports what was rebuilt.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "render/frame_renderer.h"
#include "scene/scene_file.h"

namespace lt {
namespace {

namespace fs = std::filesystem;

// Line A from (0,0) to (20,0) mm at z = 0.2 mm during [0.01, 1.01] s, 20 mm/s.
const char* kLine = ";Layer height: 0.2\nG0 F1200 Z0.2\nG1 X20 E0.8\nG0 Y10\n";

// The demo print scene's scanner, tiny: the camera 60 mm above the bed looking
// down, 8 mm behind the nozzle, its laser line across the path under the camera.
// Frames: one dim frame per 10 ms (100 us exposure).
std::string Scene() {
  return std::string(R"({"objects": [{"name": "bed", "gltf": ")") + LT_SOURCE_DIR +
         R"(/scenes/demo/print_bed.glb"}],
  "print": {},
  "sensor": {
    "camera": {"resolution": [64, 48], "pixel_pitch_um": 4.8, "focal_length_mm": 4, "f_number": 4},
    "image_sensor": {"bit_depth": 10, "full_well_e": 10000, "system_gain_dn_per_e": 0.1, "dark_noise_e": 8},
    "lasers": [{"power_mw": 5, "wavelength_nm": 650, "fan_angle_deg": 30,
                "cam_from_projector": {"translation_m": [0, 0.03, 0], "rotation_rpy_deg": [26.565, 0, 0]}}],
    "shutter": {"frame_period_ms": 10, "cycle": [{"exposure_us": 100, "laser": true}]}},
  "motion": {"type": "gcode", "file": "line.gcode", "orientation": "fixed",
             "nozzle_from_cam": {"translation_m": [-0.008, 0, -0.06], "rotation_rpy_deg": [0, 0, 90]}},
  "render": {"spp": 1, "max_bounces": 1, "frames": 200}})";
}

struct PrintScene {
  fs::path dir = fs::temp_directory_path() / ("lt_print_render_" + std::to_string(::getpid()));
  SceneFile scene;
  std::shared_ptr<SceneGeometry> geometry;
  std::unique_ptr<EmbreeScene> embree;
  PrintScene() {
    fs::create_directories(dir);
    std::ofstream(dir / "line.gcode") << kLine;
    scene = ParseSceneText(Scene(), "scene.json", dir);
    geometry = std::make_shared<SceneGeometry>(LoadSceneGeometry(scene));
    embree = std::make_unique<EmbreeScene>(geometry);
  }
  ~PrintScene() { fs::remove_all(dir); }
  bool IsPrint(double instance) const {
    return instance >= 0 && geometry->instances[size_t(instance)].object == scene.objects.size();
  }
};

TEST(PrintRender, StripeCentresLieOnTheBeadPrintedByTheFrameTime) {
  PrintScene s;
  FrameRenderer renderer(s.scene, *s.embree);
  // Frame 5 (t = 50 ms): the nozzle at x = 0.8 mm, the laser line 8 mm behind it
  // (x = -7.2 mm): nothing printed there, the stripe lies on the bed.
  RenderedFrame early = renderer.Render(5);
  ASSERT_FALSE(early.centers.empty());
  for (const StripeCenter& c : early.centers) EXPECT_NEAR(c.p_world.z(), 0.0, 1e-9);
  for (float id : early.gt.instance.pixels) EXPECT_FALSE(s.IsPrint(id));
  // Frame 80 (t = 0.8 s): the nozzle at x = 15.8 mm, the line at x = 7.8 mm crosses
  // the bead (0.45 mm wide: the G-code's extrusion is that of a 0.45 x 0.2 mm stadium).
  RenderedFrame late = renderer.Render(80);
  EXPECT_GT(late.stats.print_triangles, 0u);
  EXPECT_EQ(late.stats.print_chunks_rebuilt, 1u);
  int on_top = 0, on_bed = 0;
  for (const StripeCenter& c : late.centers) {
    const double y = std::abs(c.p_world.y());
    if (y < 0.1e-3) {
      // The flat top of the stadium: exactly the layer height (float mesh: 1e-9 m).
      EXPECT_NEAR(c.p_world.z(), 0.2e-3, 1e-9) << c.u << " " << c.v;
      EXPECT_NEAR(c.p_world.x(), 7.8e-3, 0.1e-3);  // where the sheet crosses the bead, nearly below the camera
      ++on_top;
    } else if (y > 0.3e-3) {
      EXPECT_NEAR(c.p_world.z(), 0.0, 1e-9);
      ++on_bed;
    }
  }
  EXPECT_GE(on_top, 2);
  EXPECT_GT(on_bed, 10);
  int print_pixels = 0;
  for (float id : late.gt.instance.pixels) print_pixels += s.IsPrint(id);
  EXPECT_GT(print_pixels, 0);
  // The same frame again: nothing to rebuild (the bead under way is rebuilt only
  // when the time changes).
  RenderedFrame again = renderer.Render(80);
  EXPECT_EQ(again.stats.print_chunks_rebuilt, 0u);
  EXPECT_EQ(again.stats.print_triangles, late.stats.print_triangles);
}

TEST(PrintRender, NeedsAMutableScene) {
  PrintScene s;
  const EmbreeScene& fixed = *s.embree;
  EXPECT_THROW(FrameRenderer(s.scene, fixed), std::invalid_argument);
}

}  // namespace
}  // namespace lt

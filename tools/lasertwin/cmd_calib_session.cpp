// `lasertwin calib-session --out SCENE_DIR [--rig RIG_SCENE.json] [--rows R
// --cols C --square-mm S] [--views N] [--arm] [--seed N] ...`: writes a
// calibration session as a scene (scene/calib_session.h): a checkerboard glTF,
// the pose list of the views and a scene.json to render with `lasertwin render`.
#include <cmath>
#include <iostream>
#include <memory>

#include "core/error.h"
#include "scene/calib_session.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {
namespace {

struct CalibSessionArgs {
  std::string out;
  std::string rig = "scenes/demo/scene.json";
  double square_mm = 3;
  double min_distance_mm = 72, max_distance_mm = 90;
  bool quiet = false;
  CalibSessionOptions options;
};

void Run(CalibSessionArgs& a) {
  CalibSessionOptions& o = a.options;
  o.rig_scene = a.rig;
  o.square_m = a.square_mm * 1e-3;
  o.min_distance_m = a.min_distance_mm * 1e-3;
  o.max_distance_m = a.max_distance_mm * 1e-3;
  const CalibSession s = WriteCalibSession(o, a.out);
  if (a.quiet) return;
  double tilt_lo = 1e9, tilt_hi = 0;
  for (const auto& v : s.views) {
    tilt_lo = std::min(tilt_lo, v.tilt_deg);
    tilt_hi = std::max(tilt_hi, v.tilt_deg);
  }
  std::cerr << "wrote a calibration session of " << s.views.size() << " views (" << s.frames
            << " frames: bright, dim, ...; board tilts " << std::lround(tilt_lo) << "-" << std::lround(tilt_hi)
            << " deg) of a " << o.rows << " x " << o.cols << " board to " << a.out << "/scene.json"
            << (o.arm ? " (pose list of world_from_tool, camera by tool_from_cam)" : "") << "\nrender it with: lasertwin render "
            << a.out << "/scene.json --out RUN_DIR\n";
}

void Add(CLI::App& app) {
  auto args = std::make_shared<CalibSessionArgs>();
  auto* cmd = app.add_subcommand("calib-session",
                                 "Write a checkerboard calibration session (board glTF, poses, scene.json) to render");
  auto& o = args->options;
  cmd->add_option("--out", args->out, "Folder to write the session scene into")->required();
  cmd->add_option("--rig", args->rig, "Scene file whose sensor section is the scanner")->capture_default_str();
  cmd->add_option("--rows", o.rows, "Inner corners down a column")->capture_default_str();
  cmd->add_option("--cols", o.cols, "Inner corners along a row")->capture_default_str();
  cmd->add_option("--square-mm", args->square_mm, "Square size (mm)")->capture_default_str();
  cmd->add_option("--margin-squares", o.margin_squares, "White border (squares)")->capture_default_str();
  cmd->add_option("--views", o.views, "Number of board poses")->capture_default_str();
  cmd->add_option("--binning", o.binning, "Camera pixels binned n x n: resolution / n; the sensor sums their charge (full well x n^2, gain / n^2), so images keep the unbinned level")->capture_default_str();
  cmd->add_option("--min-tilt-deg", o.min_tilt_deg, "Smallest board tilt")->capture_default_str();
  cmd->add_option("--max-tilt-deg", o.max_tilt_deg, "Largest board tilt")->capture_default_str();
  cmd->add_option("--min-distance-mm", args->min_distance_mm, "Nearest board centre")->capture_default_str();
  cmd->add_option("--max-distance-mm", args->max_distance_mm, "Farthest board centre")->capture_default_str();
  cmd->add_option("--spp", o.spp, "Samples per pixel of the session scene")->capture_default_str();
  cmd->add_option("--seed", o.seed, "Seed of the poses and the scene")->capture_default_str();
  cmd->add_flag("--arm", o.arm, "The rig rides on a robot tool: poses are world_from_tool (hand-eye session)");
  cmd->add_flag("--quiet", args->quiet, "No summary on stderr");
  cmd->callback([args] { Run(*args); });
}

LT_REGISTER_COMMAND("calib-session", Add);

}  // namespace
}  // namespace lt::cli

// The inputs of `lasertwin calibrate` (tools/lasertwin/calibrate_inputs.h).
#include "tools/lasertwin/calibrate_inputs.h"

#include "tools/lasertwin/calib_camera_arg.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "core/error.h"
#include "pipeline/run_folder_reader.h"

namespace lt::cli {

std::string Fmt(const char* format, double a, double b, double c, double d) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

void Warn(const std::string& message) { std::cerr << "lasertwin: warning: " << message << "\n"; }

CheckerboardSpec Board(const CalibrateArgs& a) {
  if (a.rows > 0 || a.cols > 0 || a.square_mm > 0) {
    if (a.rows <= 0 || a.cols <= 0 || a.square_mm <= 0) {
      throw InputError("--rows/--cols/--square-mm", "give all three, or none (then the board is read from a file)");
    }
    CheckerboardSpec b;
    b.rows = a.rows;
    b.cols = a.cols;
    b.square_m = a.square_mm * 1e-3;
    b.Check();
    return b;
  }
  if (a.board.empty() && !std::filesystem::exists(std::filesystem::path(a.run_dir) / "scene.json")) {
    throw InputError(a.run_dir, "no scene.json to find the session's checkerboard.json in: give the board with "
                                "--board FILE or --rows, --cols and --square-mm (inner corners)");
  }
  return ReadCheckerboardFile(a.board.empty() ? FindSessionBoardFile(a.run_dir) : std::filesystem::path(a.board));
}

// A run folder has a manifest; any other folder is one of photographs.
bool IsRunFolder(const std::string& dir) { return std::filesystem::exists(std::filesystem::path(dir) / "manifest.jsonl"); }

CalibrationFile InputFile(const CalibrateArgs& a) {
  const CalibrationFileOptions options = ParseCalibCamera(a.calib, a.calib_camera);
  if (a.calib.empty()) return {};
  CalibrationFile f = ReadCalibrationFile(a.calib, options);
  for (const std::string& w : CalibrationFileWarnings(f, a.calib, "not kept in the output")) Warn(w);
  return f;
}

// --bayer: the raw frames' mosaic, for every step (the corners of the bright
// frames, the laser step's stripes); unset: rig.json's color_filter.
std::optional<ColorFilter> Bayer(const CalibrateArgs& a) {
  if (a.extraction.bayer.empty()) return std::nullopt;
  return ParseBayerPattern(a.extraction.bayer, "--bayer");
}


// The session's frames as scan reads them; a folder without a rig takes
// --calib's camera (and its laser planes) when `with_camera`.
SessionRun Session(const CalibrateArgs& a, const CalibrationFile& in, bool with_camera) {
  SessionCaptureOptions o;
  o.color_filter = Bayer(a);
  o.shutter = ParseShutterPattern(a.shutter, "--shutter");
  o.pose_file = a.pose_args.Parse();
  if (!a.pose_args.poses.empty() && a.step == "hand-eye") o.poses = a.pose_args.poses;  // the others warn
  o.bit_depth = a.bit_depth;
  if (with_camera && in.camera) {
    o.camera = in.MakeCamera(CameraParams{}, a.calib);
    o.planes_in_cam = in.laser_planes;
    o.camera_source = a.calib;
  }
  SessionRun run = ReadSessionRun(a.run_dir, o, Warn);
  if (with_camera && !run.has_camera) {
    throw InputError(a.run_dir, "no rig.json or scene.json, so no camera: give the calibrated camera with --calib "
                                "FILE (from `lasertwin calibrate camera`, or OpenCV's YAML)");
  }
  if (!run.rig_in_run) {
    // The black level is the laser step's only (the corners need none).
    NoRigAssumptions assumed;
    assumed.black_level_zero = a.step == "laser" && a.extraction.background.empty();
    assumed.mono = a.extraction.bayer.empty();
    if (assumed.black_level_zero || assumed.mono) {
      assumed.camera_source = run.has_camera ? run.rig.source.string() : "";
      Warn(NoRigWarning(a.run_dir, assumed));
    }
  }
  if (!a.quiet && run.from_listing) {
    std::cerr << "frames: the " << run.frames.size() << " image files of " << run.source.string()
              << " in file name order (no manifest.jsonl), " << a.shutter << "\n";
  }
  if (!a.quiet && !run.pose_source.empty()) std::cerr << "poses: " << run.pose_source << "\n";
  return run;
}

// The refusal's hint when the shutter pattern may be the wrong way round.
std::string Hint(const SessionRun& run, const std::vector<SessionView>& views) {
  const std::string h = ShutterHint(run, views);
  return h.empty() ? h : "; " + h;
}

// The camera for the laser and hand-eye steps: --calib's, else the run's true one.
Camera StepCamera(const CalibrateArgs& a, const CalibrationFile& in, const RunRig& rig) {
  if (in.camera) {
    if (in.camera->width != rig.camera.width() || in.camera->height != rig.camera.height()) {
      throw InputError(a.calib, "the calibrated camera is " + std::to_string(in.camera->width) + "x" +
                                    std::to_string(in.camera->height) + " but the run's is " +
                                    std::to_string(rig.camera.width()) + "x" + std::to_string(rig.camera.height()));
    }
    return in.MakeCamera(rig.camera.params(), a.calib);
  }
  Warn("no calibrated camera (--calib IN.yaml with a camera part): using the run's true camera from " +
       rig.source.string());
  return rig.camera;
}

void PrintSkipped(const std::vector<SessionView>& views) {
  for (const SessionView& v : views) {
    if (!v.detection.ok) Warn("frame " + std::to_string(v.bright_frame) + ": " + v.detection.reason);
    if (v.detection.ok && v.detection.other_scales_tried > 0) {
      std::cerr << "lasertwin: note: frame " << v.bright_frame << ": board found at sigma_px = "
                << Fmt("%g", v.detection.sigma_px) << ", not at the requested scale\n";
    }
  }
}

}  // namespace lt::cli

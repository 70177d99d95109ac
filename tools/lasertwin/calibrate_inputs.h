// The inputs of `lasertwin calibrate` (tools/lasertwin/cmd_calibrate.cpp): its
// options, and what every step reads from them: the board, the calibration file
// to start from, the session's frames as scan reads them, the camera, and the
// warnings and notes on what was assumed or skipped.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/calib_session.h"
#include "pipeline/calibration_file.h"
#include "tools/lasertwin/extraction_args.h"
#include "tools/lasertwin/pose_file_args.h"

namespace lt::cli {

struct CalibrateArgs {
  std::string step;
  std::string run_dir;
  std::string out;
  std::string calib;
  std::string calib_camera;  // --calib-camera: the camera of a --calib file of several
  std::string board;
  int rows = 0, cols = 0;
  double square_mm = 0;
  std::string model = "brown_conrady";
  bool fix_k3 = false;
  int planes = 0;
  bool quiet = false;
  std::string shutter = "recorded";
  PoseFileArgs pose_args;  // the tool's poses
  int bit_depth = 0;
  std::string axis;  // laser: rows | cols; empty: from the planes, else the frames
  ExtractionArgs extraction;  // laser: the dim frames' extraction, as scan's
};

// printf-style text of up to four numbers.
std::string Fmt(const char* format, double a, double b = 0, double c = 0, double d = 0);
void Warn(const std::string& message);

// The board: --rows/--cols/--square-mm, --board FILE, or the session's checkerboard.json.
CheckerboardSpec Board(const CalibrateArgs& a);
// A run folder has a manifest; any other folder is one of photographs.
bool IsRunFolder(const std::string& dir);
// --calib's file (empty without one), its ignored keys and warnings printed.
CalibrationFile InputFile(const CalibrateArgs& a);
// --bayer: the raw frames' mosaic; unset: rig.json's color_filter.
std::optional<ColorFilter> Bayer(const CalibrateArgs& a);
// The session's frames as scan reads them; a folder without a rig takes
// --calib's camera (and its laser planes) when `with_camera`.
SessionRun Session(const CalibrateArgs& a, const CalibrationFile& in, bool with_camera);
// "; HINT" when the shutter pattern may be the wrong way round, else "".
std::string Hint(const SessionRun& run, const std::vector<SessionView>& views);
// The camera for the laser and hand-eye steps: --calib's, else the run's true one.
Camera StepCamera(const CalibrateArgs& a, const CalibrationFile& in, const RunRig& rig);
// Warnings for the views whose board was not found, notes for those found at another scale.
void PrintSkipped(const std::vector<SessionView>& views);

}  // namespace lt::cli

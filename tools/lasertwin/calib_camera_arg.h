// --calib-camera NAME beside --calib, read alike by `scan` and `calibrate`: which
// camera of a calibration file of several (pipeline/calibration_file.h,
// CalibrationFileOptions; docs/pipeline.md, "Camera files of other tools").
#pragma once

#include <string>

#include "core/error.h"
#include "pipeline/calibration_file.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {

inline void DeclareCalibCamera(CLI::App* cmd, std::string* camera) {
  cmd->add_option("--calib-camera", *camera,
                  "NAME: the camera read from a --calib file of several: a Kalibr camchain's key (cam1), a "
                  "VINS-Fusion config's camera (cam1: its cam1_calib file), a COLMAP cameras.txt's CAMERA_ID; "
                  "needed when the file holds several");
}

// Throws lt::InputError naming the option when it is given without --calib.
inline CalibrationFileOptions ParseCalibCamera(const std::string& calib, const std::string& camera) {
  if (calib.empty() && !camera.empty()) throw InputError("--calib-camera", "picks a camera of --calib's file: give --calib");
  CalibrationFileOptions o;
  if (!camera.empty()) o.camera = camera;
  return o;
}

}  // namespace lt::cli

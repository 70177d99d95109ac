// Calibration results into a calibration file (pipeline/calibration_file.h,
// OpenCV YAML): the camera's intrinsics and distortion, the laser planes by
// plane id, and the hand-eye transform tool_from_cam.
#pragma once

#include <vector>

#include "pipeline/calib_camera.h"
#include "pipeline/calib_hand_eye.h"
#include "pipeline/calib_laser_plane.h"
#include "pipeline/calibration_file.h"

namespace lt {

// Any of the three may be null (that part of the file stays empty). Throws
// lt::InputError when a given result was refused (with its reason), or when
// the plane ids are not 0, 1, ..., N−1 (the file numbers planes by position).
CalibrationFile MakeCalibrationFile(const CameraCalibrationResult* camera, const std::vector<LaserPlaneFit>* planes,
                                    const HandEyeResult* hand_eye);

}  // namespace lt

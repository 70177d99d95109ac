#include "pipeline/calib_output.h"

#include "core/error.h"

namespace lt {

CalibrationFile MakeCalibrationFile(const CameraCalibrationResult* camera, const std::vector<LaserPlaneFit>* planes,
                                    const HandEyeResult* hand_eye) {
  CalibrationFile file;
  if (camera) {
    if (!camera->ok) throw InputError("", "the camera calibration was refused: " + camera->reason);
    const CameraParams& p = camera->camera;
    CalibratedCamera c;
    c.width = p.width;
    c.height = p.height;
    c.fx = p.fx, c.fy = p.fy, c.cx = p.cx, c.cy = p.cy;
    c.distortion = p.distortion;
    c.brown_conrady = p.brown_conrady;
    c.fisheye = p.fisheye;
    file.camera = c;
  }
  if (planes) {
    for (size_t k = 0; k < planes->size(); ++k) {
      const LaserPlaneFit& fit = (*planes)[k];
      if (fit.plane_id != int(k)) {
        throw InputError("", "laser plane " + std::to_string(k) + " is missing (the fits have plane ids " +
                                 std::to_string(planes->front().plane_id) + " to " +
                                 std::to_string(planes->back().plane_id) + "; the file numbers planes 0, 1, ...)");
      }
      if (!fit.ok) throw InputError("", "the fit of laser plane " + std::to_string(k) + " was refused: " + fit.reason);
      file.laser_planes.push_back(fit.plane);
    }
  }
  if (hand_eye) {
    if (!hand_eye->ok) throw InputError("", "the hand-eye calibration was refused: " + hand_eye->reason);
    file.tool_from_cam = hand_eye->tool_from_cam;
  }
  return file;
}

}  // namespace lt

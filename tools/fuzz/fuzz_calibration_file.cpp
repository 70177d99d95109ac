// Calibration files whole (pipeline/calibration_file.h: ReadCalibrationFile):
// OpenCV YAML / XML, COLMAP, ROS, Kalibr, camodocal, VINS-Fusion; the camera built.
// The first byte, when it is '@', asks for camera "cam1" (--calib-camera).
#include "fuzz_common.h"
#include "pipeline/calibration_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lt::CalibrationFileOptions options;
  if (size > 0 && data[0] == '@') {
    options.camera = "cam1";
    ++data;
    --size;
  }
  const std::filesystem::path path = lt::fuzz::WriteScratch("calib.yaml", data, size);
  lt::fuzz::ExpectCleanErrors([&] {
    const lt::CalibrationFile c = lt::ReadCalibrationFile(path, options);
    c.MakeCamera(lt::CameraParams{}, path.string());
    lt::CalibrationFileWarnings(c, path.string(), "ignored");
  });
  return 0;
}

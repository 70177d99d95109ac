// COLMAP cameras.txt (pipeline/camera_file_formats.h: ReadColmapCameras).
#include "fuzz_common.h"
#include "pipeline/calibration_file.h"
#include "pipeline/camera_file_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lt::fuzz::ExpectCleanErrors([&] {
    lt::CalibrationFile out;
    lt::ReadColmapCameras(lt::fuzz::Text(data, size), "cameras.txt", std::nullopt, &out);
  });
  lt::fuzz::ExpectCleanErrors([&] {
    lt::CalibrationFile out;
    lt::ReadColmapCameras(lt::fuzz::Text(data, size), "cameras.txt", std::string("1"), &out);
  });
  return 0;
}

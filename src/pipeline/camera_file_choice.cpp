// Choosing one camera of a file that holds several (--calib-camera,
// pipeline/camera_file_formats.h): a Kalibr camchain's cam0, cam1, ..., a
// VINS-Fusion config's cam0_calib, cam1_calib, a COLMAP cameras.txt's ids.
#include "core/error.h"
#include "pipeline/camera_file_formats.h"

namespace lt {

namespace {

// 'a', 'b', 'c' (the first 12 of more, then how many in all).
std::string Listed(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size() && i < 12; ++i) s += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > 12) s += ", ... (" + std::to_string(names.size()) + " in all)";
  return s;
}

}  // namespace

size_t ChooseCamera(const std::vector<std::string>& names, const std::vector<std::string>& wheres,
                    const std::optional<std::string>& camera, const std::string& what) {
  if (camera) {
    for (size_t i = 0; i < names.size(); ++i) {
      if (names[i] == *camera) return i;
    }
    throw InputError(wheres[0], "no camera '" + *camera + "' in " + what + ": its " +
                                    (names.size() == 1 ? "camera is " + Listed(names) + " (drop --calib-camera to read it)"
                                                       : "cameras are " + Listed(names)));
  }
  if (names.size() > 1) {
    throw InputError(wheres[1], what + " of " + std::to_string(names.size()) +
                                    " cameras: give --calib-camera with the scanner camera's: " + Listed(names));
  }
  return 0;
}

void CheckNoCameraChosen(const std::optional<std::string>& camera, const std::string& file, const std::string& what) {
  if (!camera) return;
  throw InputError(file, "--calib-camera '" + *camera + "': " + what +
                             " holds one camera and names none (drop --calib-camera to read it); --calib-camera "
                             "picks a camera of a Kalibr camchain (cam1), a VINS-Fusion config (cam1, its cam1_calib "
                             "file) or a COLMAP cameras.txt (a CAMERA_ID)");
}

}  // namespace lt

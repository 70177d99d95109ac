// COLMAP's cameras.txt for `--calib` (pipeline/camera_file_formats.h): one
// camera line (of several, the one whose CAMERA_ID --calib-camera gives), its principal point moved from COLMAP's pixel convention
// (pixel (0,0)'s centre at (0.5, 0.5), as COLMAP's documentation of its
// keypoints states) to lasertwin's and OpenCV's ((0,0)).
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/error.h"
#include "pipeline/camera_file_formats.h"

namespace lt {

bool ReadColmapCameras(const std::string& text, const std::string& file, const std::optional<std::string>& camera,
                       CalibrationFile* out) {
  struct Row {
    int line;
    std::vector<std::string> tokens;
  };
  std::vector<Row> rows;
  std::istringstream in(text);
  std::string raw;
  auto integer = [](const std::string& t) {
    return !t.empty() && t.find_first_not_of("0123456789") == std::string::npos && t.size() < 9;
  };
  for (int no = 1; std::getline(in, raw); ++no) {
    std::istringstream words(raw);
    Row r{no, {}};
    for (std::string w; words >> w;) r.tokens.push_back(w);
    if (r.tokens.empty() || r.tokens[0][0] == '#') continue;
    // CAMERA_ID MODEL WIDTH HEIGHT PARAMS...: anything else is not COLMAP's.
    if (r.tokens.size() < 5 || !integer(r.tokens[0]) || !integer(r.tokens[2]) || !integer(r.tokens[3]) ||
        r.tokens[1].find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ_") != std::string::npos) {
      return false;
    }
    rows.push_back(std::move(r));
  }
  if (rows.empty()) return false;
  std::vector<std::string> ids, wheres;
  for (const Row& r : rows) ids.push_back(r.tokens[0]), wheres.push_back(file + ":" + std::to_string(r.line));
  const Row& r = rows[ChooseCamera(ids, wheres, camera, "a COLMAP cameras.txt")];
  const std::string where = file + ":" + std::to_string(r.line);
  const std::string& model = r.tokens[1];
  std::vector<double> p;
  for (size_t i = 4; i < r.tokens.size(); ++i) {
    char* end = nullptr;
    const double v = std::strtod(r.tokens[i].c_str(), &end);
    if (*end != '\0' || !std::isfinite(v)) {
      throw InputError(where, "COLMAP camera parameter " + std::to_string(i - 4) + " is not a number: '" + r.tokens[i] + "'");
    }
    p.push_back(v);
  }
  // Parameter counts and order as COLMAP's camera models define them.
  struct Model {
    const char* name;
    size_t count;
  };
  static const Model kModels[] = {{"SIMPLE_PINHOLE", 3}, {"PINHOLE", 4}, {"SIMPLE_RADIAL", 4}, {"RADIAL", 5},
                                  {"OPENCV", 8},         {"FULL_OPENCV", 12}, {"OPENCV_FISHEYE", 8}};
  const Model* m = nullptr;
  for (const Model& k : kModels) {
    if (model == k.name) m = &k;
  }
  if (!m) {
    throw InputError(where, "COLMAP camera model " + model +
                                ": lasertwin reads SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV "
                                "and OPENCV_FISHEYE");
  }
  if (p.size() != m->count) {
    throw InputError(where, "COLMAP " + model + " has " + std::to_string(m->count) + " parameters, got " +
                                std::to_string(p.size()));
  }
  const bool one_focal = model == "SIMPLE_PINHOLE" || model == "SIMPLE_RADIAL" || model == "RADIAL";
  const double fx = p[0], fy = one_focal ? p[0] : p[1];
  const size_t c0 = one_focal ? 1 : 2;
  CalibratedCamera c;
  c.width = int(std::strtol(r.tokens[2].c_str(), nullptr, 10));
  c.height = int(std::strtol(r.tokens[3].c_str(), nullptr, 10));
  if (c.width < 1 || c.height < 1) throw InputError(where, "COLMAP camera: width and height must be >= 1");
  // COLMAP's pixel (0,0) has its centre at (0.5, 0.5); lasertwin's at (0, 0).
  SetCameraMatrix({fx, 0, p[c0] - 0.5, 0, fy, p[c0 + 1] - 0.5, 0, 0, 1}, where, "COLMAP " + model, &c);
  const std::vector<double> d(p.begin() + long(c0 + 2), p.end());
  if (model == "SIMPLE_RADIAL") {
    SetDistortion("brown_conrady", {d[0], 0, 0, 0}, where, where, "COLMAP SIMPLE_RADIAL k", &c);
  } else if (model == "RADIAL") {
    SetDistortion("brown_conrady", {d[0], d[1], 0, 0}, where, where, "COLMAP RADIAL k1 k2", &c);
  } else if (model == "OPENCV" || model == "FULL_OPENCV") {
    // FULL_OPENCV: k1 k2 p1 p2 k3 k4 k5 k6, OpenCV's rational model (8 values).
    SetDistortion("brown_conrady", d, where, where, "COLMAP " + model + " distortion", &c);
  } else if (model == "OPENCV_FISHEYE") {
    SetDistortion("fisheye", d, where, where, "COLMAP OPENCV_FISHEYE distortion", &c);
  }
  *out = CalibrationFile{};
  out->camera = c;
  return true;
}

}  // namespace lt

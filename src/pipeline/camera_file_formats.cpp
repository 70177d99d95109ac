#include "pipeline/camera_file_formats.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/yaml_scalar.h"

namespace lt {

namespace {

// Node access with errors at the node's line.
class Reader {
 public:
  Reader(std::string file, CalibrationFile* out) : file_(std::move(file)), out_(out) {}

  std::string Where(const YamlNode& n) const { return file_ + ":" + std::to_string(n.line); }
  [[noreturn]] void Fail(const YamlNode& n, const std::string& message) const {
    throw InputError(Where(n), message);
  }
  [[noreturn]] void Fail(const std::string& message) const { throw InputError(file_, message); }

  // The typed reads (pipeline/yaml_scalar.h), errors at the node's line naming `name`.
  YamlValue Value(const YamlNode& n, const std::string& name) const {
    return {n.kind == YamlNode::Kind::kScalar ? &n.scalar : nullptr, n.quoted, name, Where(n)};
  }
  double Number(const YamlNode& n, const std::string& name) const { return YamlNumber(Value(n, name)); }
  int Integer(const YamlNode& n, const std::string& name, int lo, int hi) const {
    return int(YamlInteger(Value(n, name), lo, hi));
  }
  std::string String(const YamlNode& n, const std::string& name) const { return YamlString(Value(n, name)); }
  std::vector<double> Numbers(const YamlNode& n, const std::string& name) const {
    if (n.kind == YamlNode::Kind::kNull) return {};
    if (n.kind != YamlNode::Kind::kSeq) Fail(n, name + " must be a sequence of numbers [a, b, ...]");
    std::vector<double> v;
    for (const YamlNode& e : n.seq) v.push_back(Number(e, name + " value " + std::to_string(v.size())));
    return v;
  }
  const YamlNode& Required(const YamlNode& map, const std::string& key, const std::string& what) const {
    const YamlNode* n = map.Find(key);
    if (!n) Fail(map, what + " needs '" + key + "'");
    return *n;
  }
  // A ROS matrix {rows, cols, data}: its values, rows x cols of them.
  std::vector<double> Matrix(const YamlNode& n, const std::string& name, int rows, int cols) const {
    if (n.kind != YamlNode::Kind::kMap) Fail(n, name + " must be a matrix {rows, cols, data}");
    const int r = Integer(Required(n, "rows", name), name + ": rows", 0, 1000);
    const int c = Integer(Required(n, "cols", name), name + ": cols", 0, 1000);
    for (const auto& [key, value] : n.map) {
      if (key != "rows" && key != "cols" && key != "data" && key != "dt") Fail(value, name + ": unknown key '" + key + "'");
    }
    std::vector<double> d = Numbers(Required(n, "data", name), name + ": data");
    if (d.size() != size_t(r) * size_t(c)) {
      Fail(n, name + " is " + std::to_string(r) + "x" + std::to_string(c) + " and needs " + std::to_string(r * c) +
                  " values, got " + std::to_string(d.size()));
    }
    if ((rows > 0 && r != rows) || (cols > 0 && c != cols)) {
      Fail(n, name + " must be " + std::to_string(rows) + "x" + std::to_string(cols) + ", got " + std::to_string(r) +
                  "x" + std::to_string(c));
    }
    return d;
  }
  void Ignore(const std::string& key) const { out_->ignored_keys.push_back(key); }

  // A rectification that is not the identity: a stereo pair's.
  void CheckRectification(const std::vector<double>& r, const YamlNode& n, const std::string& name) const {
    if (r.empty()) return;
    const double id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double diff = 0;
    for (int k = 0; k < 9 && k < int(r.size()); ++k) diff = std::max(diff, std::abs(r[size_t(k)] - id[k]));
    if (diff > 1e-9) {
      out_->warnings.push_back(Where(n) + ": " + name +
           " is not the identity (a stereo pair's rectification): the camera matrix and distortion are read for "
           "the raw images, in the unrectified camera's frame; the rectified projection is not used");
    }
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
  CalibrationFile* out_;
};

bool IsCameraKey(const std::string& key) {
  if (key.size() < 4 || key.rfind("cam", 0) != 0) return false;
  for (size_t i = 3; i < key.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(key[i]))) return false;
  }
  return true;
}

// A file of one camera, named by `key` (camera_name) or not: `camera` must name it.
void ChooseNamed(const Reader& r, const YamlNode& root, const char* key, const std::optional<std::string>& camera,
                 const std::string& what) {
  const YamlNode* n = root.Find(key);
  if (!camera) return;
  if (!n || n->kind != YamlNode::Kind::kScalar) CheckNoCameraChosen(camera, r.file(), what);
  ChooseCamera({n->scalar}, {r.Where(*n)}, camera, what + " (its " + key + ")");
}

// ROS camera_info as camera_calibration_parsers write it.
void ReadRosFile(const Reader& r, const YamlNode& root, const std::optional<std::string>& camera,
                 CalibrationFile* out) {
  ChooseNamed(r, root, "camera_name", camera, "a ROS camera_info file");
  CalibratedCamera c;
  c.width = r.Integer(r.Required(root, "image_width", "a ROS camera_info file"), "image_width", 1, 1 << 16);
  c.height = r.Integer(r.Required(root, "image_height", "a ROS camera_info file"), "image_height", 1, 1 << 16);
  const YamlNode& k = *root.Find("camera_matrix");
  SetCameraMatrix(r.Matrix(k, "camera_matrix", 3, 3), r.Where(k), "camera_matrix", &c);
  // Older files have no distortion_model: ROS then takes plumb_bob.
  const YamlNode* model = root.Find("distortion_model");
  const YamlNode* d = root.Find("distortion_coefficients");
  std::vector<double> coeffs;
  if (d) coeffs = r.Matrix(*d, "distortion_coefficients", 0, 0);
  SetDistortion(model ? r.String(*model, "distortion_model") : "plumb_bob", coeffs,
                model ? r.Where(*model) : r.file(), d ? r.Where(*d) : r.file(), "distortion_coefficients", &c);
  for (const auto& [key, value] : root.map) {
    if (key == "image_width" || key == "image_height" || key == "camera_matrix" || key == "distortion_model" ||
        key == "distortion_coefficients") {
      continue;
    }
    if (key == "rectification_matrix") r.CheckRectification(r.Matrix(value, key, 3, 3), value, key);
    r.Ignore(key);
  }
  out->camera = c;
}

// A sensor_msgs/CameraInfo message as `rostopic echo` (K, D, ...) or
// `ros2 topic echo` (k, d, ...) print it.
void ReadRosMessage(const Reader& r, const YamlNode& root, const std::optional<std::string>& camera,
                    CalibrationFile* out) {
  CheckNoCameraChosen(camera, r.file(), "a ROS CameraInfo message");
  auto find = [&](const char* upper, const char* lower) {
    const YamlNode* n = root.Find(upper);
    return n ? n : root.Find(lower);
  };
  const std::string what = "a ROS CameraInfo message";
  CalibratedCamera c;
  c.width = r.Integer(r.Required(root, "width", what), "width", 1, 1 << 16);
  c.height = r.Integer(r.Required(root, "height", what), "height", 1, 1 << 16);
  const YamlNode& k = *find("K", "k");
  const std::vector<double> kv = r.Numbers(k, "K");
  if (kv.size() != 9) r.Fail(k, "K must have 9 values (3x3, row-major), got " + std::to_string(kv.size()));
  if (kv[0] == 0) r.Fail(k, "K is zero: the camera is not calibrated (ROS leaves K zero for an uncalibrated camera)");
  SetCameraMatrix(kv, r.Where(k), "K", &c);
  const YamlNode* model = root.Find("distortion_model");
  const YamlNode* d = find("D", "d");
  SetDistortion(model ? r.String(*model, "distortion_model") : "plumb_bob", d ? r.Numbers(*d, "D") : std::vector<double>{},
                model ? r.Where(*model) : r.file(), d ? r.Where(*d) : r.file(), "D", &c);
  for (const char* b : {"binning_x", "binning_y"}) {
    if (const YamlNode* n = root.Find(b)) {
      if (r.Integer(*n, b, 0, 1 << 16) > 1) {
        r.Fail(*n, std::string(b) + " is " + n->scalar +
                       ": K is for the unbinned image; lasertwin reads the camera of the images it is given");
      }
    }
  }
  if (const YamlNode* roi = root.Find("roi")) {
    for (const char* key : {"x_offset", "y_offset", "width", "height"}) {
      const YamlNode* n = roi->Find(key);
      if (n && r.Integer(*n, std::string("roi ") + key, 0, 1 << 16) != 0) {
        r.Fail(*n, std::string("roi ") + key + " is " + n->scalar +
                       ": the images are a region of the sensor, K is for the full image");
      }
    }
  }
  for (const auto& [key, value] : root.map) {
    if (key == "R" || key == "r") r.CheckRectification(r.Numbers(value, "R"), value, "R");
    if (key != "width" && key != "height" && key != "K" && key != "k" && key != "D" && key != "d" &&
        key != "distortion_model") {
      r.Ignore(key);
    }
  }
  out->camera = c;
}

// A Kalibr camchain: the camera `camera` names (cam1), else its one camera. Its
// extrinsics (T_cam_imu, cam1's T_cn_cnm1 = cam1_from_cam0) are not read.
void ReadKalibr(const Reader& r, const YamlNode& root, const std::optional<std::string>& camera, CalibrationFile* out) {
  std::vector<std::string> cams, wheres;
  for (const auto& [key, value] : root.map) {
    if (IsCameraKey(key)) cams.push_back(key), wheres.push_back(r.Where(value));
  }
  const std::string name = cams[ChooseCamera(cams, wheres, camera, "a Kalibr camera chain")];
  const YamlNode& cam = *root.Find(name);
  if (cam.kind != YamlNode::Kind::kMap) r.Fail(cam, name + " must be a map");
  const std::string what = "Kalibr's " + name;
  if (const YamlNode* m = cam.Find("camera_model")) {
    const std::string model = r.String(*m, name + ".camera_model");
    if (model != "pinhole") {
      r.Fail(*m, name + ".camera_model is '" + model +
                     "': lasertwin's cameras are pinhole (with radtan or equidistant distortion); " + model +
                     " is another projection");
    }
  }
  CalibratedCamera c;
  const YamlNode& res = r.Required(cam, "resolution", what);
  const std::vector<double> wh = r.Numbers(res, name + ".resolution");
  if (wh.size() != 2) r.Fail(res, name + ".resolution must be [width, height]");
  c.width = r.Integer(res.seq[0], name + ".resolution width", 1, 1 << 16);
  c.height = r.Integer(res.seq[1], name + ".resolution height", 1, 1 << 16);
  const YamlNode& in = r.Required(cam, "intrinsics", what);
  const std::vector<double> f = r.Numbers(in, name + ".intrinsics");
  if (f.size() != 4) {
    r.Fail(in, name + ".intrinsics must be [fu, fv, pu, pv] for a pinhole camera, got " + std::to_string(f.size()) +
                   " values");
  }
  SetCameraMatrix({f[0], 0, f[2], 0, f[1], f[3], 0, 0, 1}, r.Where(in), name + ".intrinsics", &c);
  const YamlNode* model = cam.Find("distortion_model");
  const YamlNode* d = cam.Find("distortion_coeffs");
  std::string m = model ? r.String(*model, name + ".distortion_model") : "none";
  const std::vector<double> coeffs = d ? r.Numbers(*d, name + ".distortion_coeffs") : std::vector<double>{};
  if (m == "radtan" && coeffs.size() != 4) {
    r.Fail(d ? *d : cam, name + ".distortion_coeffs: radtan has 4 (k1 k2 r1 r2), got " + std::to_string(coeffs.size()));
  }
  if (m == "fov" || m == "brown_conrady" || m == "plumb_bob" || m == "rational_polynomial" || m == "fisheye") {
    r.Fail(*model, name + ".distortion_model '" + m + "': Kalibr's are radtan, equidistant and none; lasertwin reads "
                          "radtan and equidistant");
  }
  SetDistortion(m, coeffs, model ? r.Where(*model) : r.file(), d ? r.Where(*d) : r.file(), name + ".distortion_coeffs",
                &c);
  for (const auto& [key, value] : cam.map) {
    if (key != "camera_model" && key != "resolution" && key != "intrinsics" && key != "distortion_model" &&
        key != "distortion_coeffs") {
      r.Ignore(name + "." + key);
    }
  }
  for (const auto& [key, value] : root.map) {
    if (key != name) r.Ignore(key);
  }
  out->camera = c;
}

// camodocal's camera (VINS-Mono, VINS-Fusion).
void ReadCamodocal(const Reader& r, const YamlNode& root, const std::optional<std::string>& camera,
                   CalibrationFile* out) {
  ChooseNamed(r, root, "camera_name", camera, "camodocal's camera file");
  const YamlNode& mt = *root.Find("model_type");
  const std::string model = r.String(mt, "model_type");
  if (model != "PINHOLE" && model != "KANNALA_BRANDT") {
    r.Fail(mt, "model_type " + model + " (camodocal): lasertwin reads PINHOLE and KANNALA_BRANDT cameras; " + model +
                   " is another projection");
  }
  const std::string what = "camodocal's " + model + " camera";
  CalibratedCamera c;
  c.width = r.Integer(r.Required(root, "image_width", what), "image_width", 1, 1 << 16);
  c.height = r.Integer(r.Required(root, "image_height", what), "image_height", 1, 1 << 16);
  const YamlNode& p = r.Required(root, "projection_parameters", what);
  const YamlNode* dp = root.Find("distortion_parameters");
  auto value = [&](const YamlNode& map, const char* key, const std::string& group) {
    return r.Number(r.Required(map, key, group), group + "." + key);
  };
  if (model == "PINHOLE") {
    SetCameraMatrix({value(p, "fx", "projection_parameters"), 0, value(p, "cx", "projection_parameters"), 0,
                     value(p, "fy", "projection_parameters"), value(p, "cy", "projection_parameters"), 0, 0, 1},
                    r.Where(p), "projection_parameters", &c);
    if (!dp) r.Fail(root, what + " needs 'distortion_parameters' (k1 k2 p1 p2)");
    SetDistortion("radtan",
                  {value(*dp, "k1", "distortion_parameters"), value(*dp, "k2", "distortion_parameters"),
                   value(*dp, "p1", "distortion_parameters"), value(*dp, "p2", "distortion_parameters")},
                  r.Where(mt), r.Where(*dp), "distortion_parameters", &c);
  } else {
    // camodocal's EquidistantCamera reads k2..k5 (OpenCV's fisheye k1..k4) and
    // mu mv u0 v0 (fx fy cx cy) from projection_parameters; k's elsewhere are not read by it.
    if (!p.Find("k2") && dp && dp->Find("k2")) {
      r.Fail(*dp, "KANNALA_BRANDT: k2..k5 are under distortion_parameters, where camodocal does not read them "
                  "(it reads them from projection_parameters, as zero here): move them to projection_parameters");
    }
    SetCameraMatrix({value(p, "mu", "projection_parameters"), 0, value(p, "u0", "projection_parameters"), 0,
                     value(p, "mv", "projection_parameters"), value(p, "v0", "projection_parameters"), 0, 0, 1},
                    r.Where(p), "projection_parameters", &c);
    SetDistortion("equidistant",
                  {value(p, "k2", "projection_parameters"), value(p, "k3", "projection_parameters"),
                   value(p, "k4", "projection_parameters"), value(p, "k5", "projection_parameters")},
                  r.Where(mt), r.Where(p), "projection_parameters", &c);
  }
  for (const auto& [key, v] : root.map) {
    if (key != "model_type" && key != "image_width" && key != "image_height" && key != "projection_parameters" &&
        key != "distortion_parameters") {
      r.Ignore(key);
    }
  }
  out->camera = c;
}

// VINS-Fusion's config: cam0_calib, cam1_calib, ... naming camodocal files, the first
// num_of_cam of them (all without num_of_cam). The keys, in file order.
std::vector<std::string> VinsFusionCameras(const YamlNode& root) {
  const YamlNode* n = root.Find("num_of_cam");
  const long count = n && n->kind == YamlNode::Kind::kScalar ? std::strtol(n->scalar.c_str(), nullptr, 10) : -1;
  std::vector<std::string> keys;
  for (const auto& [key, value] : root.map) {
    const size_t at = key.size() - std::min(key.size(), size_t(6));
    if (key.compare(at, 6, "_calib") != 0 || !IsCameraKey(key.substr(0, at))) continue;
    if (count < 0 || std::strtol(key.c_str() + 3, nullptr, 10) < count) keys.push_back(key);
  }
  return keys;
}

// The camodocal file of the camera `camera` names (cam1), else of the one camera,
// read beside the config as VINS-Fusion reads it (errors in it name that file).
// Its extrinsics (body_T_cam0, body_T_cam1: imu_from_cam) are not read.
void ReadVinsFusion(const Reader& r, const YamlNode& root, const std::optional<std::string>& camera,
                    CalibrationFile* out) {
  const std::vector<std::string> keys = VinsFusionCameras(root);
  std::vector<std::string> cams, wheres;
  for (const std::string& key : keys) cams.push_back(key.substr(0, key.size() - 6)), wheres.push_back(r.Where(*root.Find(key)));
  const size_t chosen = ChooseCamera(cams, wheres, camera, "a VINS-Fusion config");
  const YamlNode& n = *root.Find(keys[chosen]);
  const std::string name = r.String(n, keys[chosen]);
  const std::filesystem::path path = std::filesystem::path(r.file()).parent_path() / name;
  if (!std::filesystem::is_regular_file(path)) {
    r.Fail(n, keys[chosen] + " '" + name + "': no such file (VINS-Fusion reads it beside the config: " + path.string() +
                  ")");
  }
  const YamlNode cam = ParseYamlTree(ReadTextFile(path, path.string()), path.string());
  if (!cam.Find("model_type")) {
    r.Fail(n, keys[chosen] + ": " + path.string() + " is not a camodocal camera file (no model_type)");
  }
  const Reader in_file(path.string(), out);
  ReadCamodocal(in_file, cam, std::nullopt, out);
  for (const auto& [key, value] : root.map) {
    if (key != keys[chosen] && key != "num_of_cam") r.Ignore(key);
  }
}

}  // namespace

bool ReadOtherCameraFile(const YamlNode& root, const std::string& file, const std::optional<std::string>& camera,
                         CalibrationFile* out) {
  if (root.kind != YamlNode::Kind::kMap) return false;
  CalibrationFile f;
  const Reader r(file, &f);
  const YamlNode* k = root.Find("camera_matrix");
  bool kalibr = false;
  for (const auto& [key, value] : root.map) {
    kalibr = kalibr || (IsCameraKey(key) && value.kind == YamlNode::Kind::kMap &&
                        (value.Find("intrinsics") || value.Find("camera_model")));
  }
  if (root.Find("model_type")) {
    ReadCamodocal(r, root, camera, &f);
  } else if (kalibr) {
    ReadKalibr(r, root, camera, &f);
  } else if (!VinsFusionCameras(root).empty()) {
    ReadVinsFusion(r, root, camera, &f);
  } else if (k && k->kind == YamlNode::Kind::kMap && k->tag.empty()) {
    ReadRosFile(r, root, camera, &f);
  } else if ((root.Find("width") || root.Find("height")) &&
             ((root.Find("K") && root.Find("K")->kind == YamlNode::Kind::kSeq) ||
              (root.Find("k") && root.Find("k")->kind == YamlNode::Kind::kSeq))) {
    // (An OpenCV file's K: !!opencv-matrix is not a message's K.)
    ReadRosMessage(r, root, camera, &f);
  } else {
    return false;
  }
  *out = std::move(f);
  return true;
}

}  // namespace lt

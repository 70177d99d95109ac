#include "pipeline/calibration_file.h"

#include <cctype>
#include <cmath>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/camera_file_formats.h"
#include "pipeline/opencv_yaml.h"
#include "pipeline/yaml_tree.h"
#include "sensor/param_error.h"

namespace lt {

namespace {

const std::set<std::string>& KnownKeys() {
  static const std::set<std::string> keys = {"image_width",      "image_height",  "camera_matrix",
                                             "distortion_model", "fisheye_model", "distortion_coefficients",
                                             "laser_planes",     "tool_from_cam", "depth_min_mm", "depth_max_mm"};
  return keys;
}

// The values of a 1xN or Nx1 matrix.
std::vector<double> VectorValues(const OpenCvYaml& y, const YamlEntry& e) {
  const YamlMatrix& m = y.Matrix(e);
  if (m.rows != 1 && m.cols != 1) {
    throw InputError(y.Where(e), e.key + " must be a 1xN or Nx1 matrix, got " + std::to_string(m.rows) + "x" +
                                     std::to_string(m.cols));
  }
  return m.data;
}

CalibratedCamera ReadCamera(const OpenCvYaml& y) {
  const YamlEntry* k = y.Find("camera_matrix");
  const YamlEntry* w = y.Find("image_width");
  const YamlEntry* h = y.Find("image_height");
  std::string missing;
  for (auto [entry, name] : {std::pair{k, "camera_matrix"}, std::pair{w, "image_width"}, std::pair{h, "image_height"}}) {
    if (!entry) missing += std::string(missing.empty() ? "" : ", ") + name;
  }
  if (!missing.empty()) {
    throw InputError(y.file(), "the camera part needs camera_matrix, image_width and image_height (missing " +
                                   missing + ")");
  }
  CalibratedCamera c;
  c.width = int(y.Integer(*w, 1, 1 << 16));
  c.height = int(y.Integer(*h, 1, 1 << 16));
  const YamlMatrix& m = y.Matrix(*k);
  if (m.rows != 3 || m.cols != 3) {
    throw InputError(y.Where(*k), "camera_matrix must be 3x3, got " + std::to_string(m.rows) + "x" +
                                      std::to_string(m.cols));
  }
  SetCameraMatrix(m.data, y.Where(*k), "camera_matrix", &c);
  const YamlEntry* dm = y.Find("distortion_model");
  std::string model = dm ? y.String(*dm) : "brown_conrady";
  // OpenCV's camera calibration sample says which model its coefficients
  // belong to by `fisheye_model: 0 | 1` (cv::fisheye's k1..k4 are 4 values,
  // as are Brown-Conrady's k1 k2 p1 p2).
  if (const YamlEntry* fm = y.Find("fisheye_model")) {
    const bool fisheye = y.Integer(*fm, 0, 1) == 1;
    const bool model_fisheye = model == "fisheye" || model == "equidistant";
    if (dm && fisheye != model_fisheye) {
      throw InputError(y.Where(*fm), "fisheye_model " + fm->scalar + " contradicts distortion_model " + model +
                                         " (line " + std::to_string(dm->line) + ")");
    }
    if (!dm) model = fisheye ? "fisheye" : "brown_conrady";
  }
  const YamlEntry* dc = y.Find("distortion_coefficients");
  if (!dc && (model == "fisheye" || model == "equidistant")) {
    throw InputError(y.file(), "distortion_model fisheye needs distortion_coefficients (k1 k2 k3 k4)");
  }
  SetDistortion(model, dc ? VectorValues(y, *dc) : std::vector<double>{}, dm ? y.Where(*dm) : y.file(),
                dc ? y.Where(*dc) : y.file(), "distortion_coefficients", &c);
  return c;
}

std::vector<Plane> ReadPlanes(const OpenCvYaml& y, const YamlEntry& e) {
  const YamlMatrix& m = y.Matrix(e);
  if (m.cols != 4) {
    throw InputError(y.Where(e), "laser_planes must be N x 4 (nx, ny, nz, d per row), got " + std::to_string(m.rows) +
                                     "x" + std::to_string(m.cols));
  }
  std::vector<Plane> planes;
  for (int r = 0; r < m.rows; ++r) {
    Eigen::Vector3d n(m.At(r, 0), m.At(r, 1), m.At(r, 2));
    const double norm = n.norm();
    if (!(norm > 1e-12) || !std::isfinite(norm)) {
      throw InputError(y.Where(e), "laser_planes: plane " + std::to_string(r) + " has a zero normal");
    }
    // Normals unit to rounding are kept as written, so that files round-trip exactly.
    const double scale = std::abs(norm - 1.0) > 1e-12 ? norm : 1.0;
    planes.push_back({n / scale, m.At(r, 3) / scale});
  }
  return planes;
}

Pose ReadRigid(const OpenCvYaml& y, const YamlEntry& e) {
  const YamlMatrix& m = y.Matrix(e);
  if (m.rows != 4 || m.cols != 4) {
    throw InputError(y.Where(e), e.key + " must be 4x4, got " + std::to_string(m.rows) + "x" + std::to_string(m.cols));
  }
  Eigen::Matrix4d t;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) t(r, c) = m.At(r, c);
  if (t(3, 0) != 0 || t(3, 1) != 0 || t(3, 2) != 0 || t(3, 3) != 1) {
    throw InputError(y.Where(e), e.key + ": the last row must be 0 0 0 1");
  }
  Eigen::Matrix3d r = t.topLeftCorner<3, 3>();
  const double err = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (err > 1e-6 || r.determinant() < 0) {
    throw InputError(y.Where(e), e.key + ": the upper-left 3x3 block must be a rotation (orthonormal to 1e-6, "
                                         "determinant +1)");
  }
  Pose p = Pose::Identity();
  p.linear() = r;  // as written, so that files round-trip exactly
  p.translation() = t.topRightCorner<3, 1>();
  return p;
}

// The file's text as OpenCvYaml's entries, unless it is another tool's camera
// file: then that camera is read into *other and nullopt returned. The YAML text
// is parsed once, its tree read as the other tools' files or OpenCV's.
std::optional<OpenCvYaml> ReadOpenCvOrOther(const std::string& text, const std::string& file,
                                            const CalibrationFileOptions& options, CalibrationFile* other) {
  if (IsOpenCvXmlText(text)) return OpenCvYaml::Parse(text, file);
  if (ReadColmapCameras(text, file, options.camera, other)) return std::nullopt;
  YamlLine first;
  YamlNode root;
  try {
    root = ParseYamlTree(text, file, &first);
  } catch (const InputError& e) {
    // A file starting %YAML: is OpenCV's: its error as it is.
    const size_t start = text.find_first_not_of(" \t\r\n");
    if (start != std::string::npos && text.compare(start, 6, "%YAML:") == 0) throw;
    throw InputError(e.where(), e.message() + " (expected a calibration file: OpenCV FileStorage YAML or XML, or "
                                              "the camera file of ROS (camera_info), Kalibr (camchain) or camodocal)");
  }
  // The camera files of other tools (ROS, Kalibr, camodocal) are recognised by their keys.
  if (ReadOtherCameraFile(root, file, options.camera, other)) return std::nullopt;
  return OpenCvYaml::Parse(root, first, file);
}

}  // namespace

CalibratedCamera CalibratedCamera::From(const Camera& camera) {
  CalibratedCamera c;
  const CameraParams& p = camera.params();
  c.width = p.width;
  c.height = p.height;
  c.fx = p.fx;
  c.fy = p.fy;
  c.cx = p.cx;
  c.cy = p.cy;
  c.distortion = p.distortion;
  c.brown_conrady = p.brown_conrady;
  c.fisheye = p.fisheye;
  return c;
}

CameraParams CalibratedCamera::ApplyTo(CameraParams base) const {
  base.width = width;
  base.height = height;
  base.fx = fx;
  base.fy = fy;
  base.cx = cx;
  base.cy = cy;
  base.distortion = distortion;
  base.brown_conrady = brown_conrady;
  base.fisheye = fisheye;
  return base;
}

Camera CalibrationFile::MakeCamera(const CameraParams& base, const std::string& file) const {
  CameraParams p = camera ? camera->ApplyTo(base) : base;
  try {
    return Camera(p);
  } catch (const ParamError& e) {
    throw InputError(file, "camera: " + std::string(e.what()));
  }
}

CalibrationFile ReadCalibrationFile(const std::filesystem::path& path, const CalibrationFileOptions& options) {
  const std::string file = path.string();
  CalibrationFile other;
  const std::optional<OpenCvYaml> opencv = ReadOpenCvOrOther(OpenCvYaml::ReadText(path), file, options, &other);
  if (!opencv) {
    other.MakeCamera(CameraParams{}, file);  // a distortion that folds inside the image
    return other;
  }
  const OpenCvYaml& y = *opencv;
  CheckNoCameraChosen(options.camera, file, "an OpenCV FileStorage file");
  CalibrationFile c;
  for (const auto& e : y.entries()) {
    if (!KnownKeys().count(e.key)) c.ignored_keys.push_back(e.key);
  }
  if (y.Find("camera_matrix") || y.Find("image_width") || y.Find("image_height") ||
      y.Find("distortion_coefficients") || y.Find("distortion_model")) {
    c.camera = ReadCamera(y);
    // Check that the camera can be built (a distortion that folds inside the image).
    c.MakeCamera(CameraParams{}, path.string());
  }
  if (const YamlEntry* e = y.Find("laser_planes")) c.laser_planes = ReadPlanes(y, *e);
  if (const YamlEntry* e = y.Find("tool_from_cam")) c.tool_from_cam = ReadRigid(y, *e);
  const YamlEntry* near = y.Find("depth_min_mm");
  const YamlEntry* far = y.Find("depth_max_mm");
  if (near || far) {
    if (!near || !far) {
      throw InputError(y.Where(near ? *near : *far), "the working range needs both depth_min_mm and depth_max_mm");
    }
    c.depth_range = DepthRange{y.Number(*near) / 1e3, y.Number(*far) / 1e3};
    c.depth_range->Check(y.Where(*far));
  }
  if (!c.camera && c.laser_planes.empty() && !c.tool_from_cam && !c.depth_range) {
    // OpenCV's stereo_calib sample writes both cameras (M1 D1 M2 D2, or K1 D1 K2 D2) without their image size.
    const bool stereo = (y.Find("M1") || y.Find("K1")) && (y.Find("M2") || y.Find("K2"));
    if (stereo) {
      throw InputError(file, "an OpenCV stereo calibration (M1 D1 M2 D2 or K1 D1 K2 D2, without the image size): "
                             "lasertwin reads one camera: write its matrix as camera_matrix and its coefficients as "
                             "distortion_coefficients, with image_width and image_height");
    }
    std::string keys;
    for (const auto& e : y.entries()) keys += (keys.empty() ? "" : ", ") + e.key;
    throw InputError(file, "holds nothing lasertwin reads: no camera (camera_matrix, image_width, image_height), "
                           "laser_planes, tool_from_cam or depth_min_mm/depth_max_mm" +
                               (keys.empty() ? std::string() : " (its keys: " + keys + ")"));
  }
  return c;
}

std::vector<std::string> CalibrationFileWarnings(const CalibrationFile& c, const std::string& file,
                                                 const std::string& fate) {
  std::vector<std::string> lines;
  if (const size_t n = c.ignored_keys.size(); n > 0) {
    // One line, however many: another tool's file (a VINS config) can hold dozens.
    const std::string keys = ListFirst(c.ignored_keys, 8);
    lines.push_back(file + ": " + (n == 1 ? "key " + keys + " is" : std::to_string(n) + " keys (" + keys + ") are") +
                    " " + fate);
  }
  lines.insert(lines.end(), c.warnings.begin(), c.warnings.end());
  return lines;
}

StorageFormat CalibrationFileFormat(const std::filesystem::path& path) {
  const std::string ext = Lower(path.extension().string());
  if (ext == ".xml") return StorageFormat::kXml;
  if (ext == ".yaml" || ext == ".yml") return StorageFormat::kYaml;
  throw InputError(path.string(), (ext.empty() ? std::string("no extension") : "unknown extension '" + ext + "'") +
                                      ": a calibration file is written as OpenCV YAML (.yaml, .yml) or OpenCV XML "
                                      "(.xml)");
}

std::string FormatCalibrationFile(const CalibrationFile& c, StorageFormat format) {
  OpenCvYamlWriter w(format);
  if (c.camera) {
    const CalibratedCamera& cam = *c.camera;
    w.Integer("image_width", cam.width);
    w.Integer("image_height", cam.height);
    w.Matrix("camera_matrix", 3, 3, {cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1});
    if (cam.distortion == DistortionModel::kFisheye) {
      w.String("distortion_model", "fisheye");
      w.Matrix("distortion_coefficients", 1, 4, {cam.fisheye.k1, cam.fisheye.k2, cam.fisheye.k3, cam.fisheye.k4});
    } else {
      const BrownConradyCoeffs b =
          cam.distortion == DistortionModel::kBrownConrady ? cam.brown_conrady : BrownConradyCoeffs{};
      w.String("distortion_model", "brown_conrady");
      w.Matrix("distortion_coefficients", 1, 5, {b.k1, b.k2, b.p1, b.p2, b.k3});
    }
  }
  if (!c.laser_planes.empty()) {
    std::vector<double> data;
    for (const Plane& p : c.laser_planes) data.insert(data.end(), {p.n.x(), p.n.y(), p.n.z(), p.d});
    w.Matrix("laser_planes", int(c.laser_planes.size()), 4, data);
  }
  if (c.tool_from_cam) {
    Eigen::Matrix4d t = c.tool_from_cam->matrix();
    std::vector<double> data;
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) data.push_back(t(r, k));
    w.Matrix("tool_from_cam", 4, 4, data);
  }
  if (c.depth_range) {
    // Millimetres to the nanometre, so 85 mm (0.085 m) is written as 85.
    w.Number("depth_min_mm", std::round(c.depth_range->near_m * 1e12) / 1e9);
    w.Number("depth_max_mm", std::round(c.depth_range->far_m * 1e12) / 1e9);
  }
  return w.text();
}

void WriteCalibrationFile(const std::filesystem::path& path, const CalibrationFile& calibration) {
  WriteFileAtomically(path, FormatCalibrationFile(calibration, CalibrationFileFormat(path)));
}

}  // namespace lt

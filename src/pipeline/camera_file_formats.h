// Camera files written by other tools, read for `--calib` beside OpenCV's
// FileStorage (pipeline/calibration_file.h). docs/pipeline.md ("Calibration
// file") lists them:
//
//   ROS camera_info YAML (camera_calibration, camera_info_manager):
//     image_width, image_height, camera_matrix {rows, cols, data},
//     distortion_model plumb_bob | rational_polynomial | equidistant,
//     distortion_coefficients {rows, cols, data}, rectification_matrix,
//     projection_matrix, camera_name; or a CameraInfo message as
//     `rostopic echo` / `ros2 topic echo` print it (width, height, K/k, D/d, R/r, ...)
//   Kalibr camchain YAML: cam0 {camera_model pinhole, intrinsics [fu fv pu pv],
//     distortion_model radtan | equidistant | none, distortion_coeffs,
//     resolution [w h], T_cam_imu, ...}, cam1 {..., T_cn_cnm1}: of several, the
//     one `camera` names (its key)
//   camodocal (VINS-Mono, VINS-Fusion) YAML: model_type PINHOLE |
//     KANNALA_BRANDT, image_width, image_height, distortion_parameters,
//     projection_parameters
//   VINS-Fusion's config: num_of_cam, cam0_calib, cam1_calib naming camodocal
//     files beside it (as VINS-Fusion reads them): the file of cam0, or of the
//     camera `camera` names (cam1)
//   COLMAP cameras.txt: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL,
//     OPENCV, FULL_OPENCV (k4..k6 0), OPENCV_FISHEYE; of several, the one
//     whose CAMERA_ID `camera` is
//
// All but COLMAP put pixel (0,0)'s centre at (0,0), as OpenCV and lasertwin
// do; COLMAP puts it at (0.5, 0.5), so its principal point is moved by half
// a pixel (cx - 0.5, cy - 0.5). No extrinsics are read (T_cam_imu, T_cn_cnm1,
// body_T_cam1 are listed as ignored keys of the chosen camera). What
// cannot be honoured (another model, a term lasertwin does not model,
// several cameras without `camera`, binning) is an error naming file:line; a
// rectification that is not the identity is a warning (K and D are read for
// the raw image). `camera` (--calib-camera) given for a file of one camera
// must name it (Kalibr's key, camera_name of ROS and camodocal files).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/calibration_file.h"
#include "pipeline/yaml_tree.h"

namespace lt {

// Sets c's intrinsics from a 3x3 row-major camera matrix [fx 0 cx; 0 fy cy; 0 0 1].
// Throws lt::InputError at `where` ("file:line") naming `name` for another
// form (skew, a last row other than 0 0 1, fx or fy <= 0).
void SetCameraMatrix(const std::vector<double>& k, const std::string& where, const std::string& name,
                     CalibratedCamera* c);

// Sets c's distortion from a model name and its coefficients:
// brown_conrady, plumb_bob, rational_polynomial, radtan: OpenCV's k1 k2 p1 p2
// [k3 [k4 k5 k6 ...]] (4, 5, 8, 12 or 14 values, those after k3 0);
// fisheye, equidistant: k1 k2 k3 k4; none: no values, or all 0. Errors name
// `where_model` for the name and `where_coeffs` (with `coeffs_name`) for the values.
void SetDistortion(const std::string& model, const std::vector<double>& d, const std::string& where_model,
                   const std::string& where_coeffs, const std::string& coeffs_name, CalibratedCamera* c);

// When `root` (a YAML file's tree) is one of the formats above, reads its
// camera into *out (camera, ignored_keys, warnings) and returns true; false
// when it is none of them (then nothing is changed).
bool ReadOtherCameraFile(const YamlNode& root, const std::string& file, const std::optional<std::string>& camera,
                         CalibrationFile* out);

// When `text` is a COLMAP cameras.txt (its lines, but for # comments,
// "CAMERA_ID MODEL WIDTH HEIGHT PARAMS..."), reads its camera into *out and
// returns true; false otherwise. Several cameras without `camera` are an error.
bool ReadColmapCameras(const std::string& text, const std::string& file, const std::optional<std::string>& camera,
                       CalibrationFile* out);

// The index of the camera `camera` (--calib-camera) names among `names` (in
// file order; `wheres` their "file:line"), else of the one camera. Throws
// lt::InputError naming every camera and the option, at wheres[1] for
// several without `camera`, at wheres[0] for a name not among them. `what`
// names the file's form ("a Kalibr camera chain").
size_t ChooseCamera(const std::vector<std::string>& names, const std::vector<std::string>& wheres,
                    const std::optional<std::string>& camera, const std::string& what);

// Throws lt::InputError naming `file` when `camera` is given for a file whose
// one camera has no name (`what`: its form, "an OpenCV FileStorage file").
void CheckNoCameraChosen(const std::optional<std::string>& camera, const std::string& file, const std::string& what);

}  // namespace lt

// The intrinsics and distortion of a camera file (pipeline/camera_file_formats.h):
// a camera matrix and a distortion model's coefficients, as each format's reader
// hands them over, checked and set in lasertwin's (OpenCV's) form.
#include <cmath>

#include "core/error.h"
#include "pipeline/camera_file_formats.h"

namespace lt {

void SetCameraMatrix(const std::vector<double>& k, const std::string& where, const std::string& name,
                     CalibratedCamera* c) {
  c->fx = k[0];
  c->fy = k[4];
  c->cx = k[2];
  c->cy = k[5];
  if (!(c->fx > 0 && c->fy > 0)) {
    throw InputError(where, name + ": fx and fy must be > 0, got " + FormatNumber(c->fx) + " and " + FormatNumber(c->fy));
  }
  if (std::abs(k[1]) > 1e-9 * c->fx) {
    throw InputError(where, name + ": skew (row 0, column 1) is not supported, got " + FormatNumber(k[1]));
  }
  if (k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1) {
    throw InputError(where, name + " must have the form [fx 0 cx; 0 fy cy; 0 0 1]");
  }
}

void SetDistortion(const std::string& model, const std::vector<double>& d, const std::string& where_model,
                   const std::string& where_coeffs, const std::string& coeffs_name, CalibratedCamera* c) {
  if (model == "fisheye" || model == "equidistant") {
    if (d.size() != 4) {
      throw InputError(where_coeffs, "fisheye " + coeffs_name + " must have 4 values (k1 k2 k3 k4), got " +
                                         std::to_string(d.size()));
    }
    c->distortion = DistortionModel::kFisheye;
    c->fisheye = {d[0], d[1], d[2], d[3]};  // all zero is still the fisheye projection (θ_d = θ)
    return;
  }
  if (model == "none") {
    for (double v : d) {
      if (v != 0) throw InputError(where_coeffs, coeffs_name + ": distortion_model none with nonzero coefficients");
    }
    c->distortion = DistortionModel::kNone;
    return;
  }
  if (model != "brown_conrady" && model != "plumb_bob" && model != "rational_polynomial" && model != "radtan") {
    throw InputError(where_model, "distortion_model must be brown_conrady (plumb_bob, rational_polynomial, radtan) or "
                                  "fisheye (equidistant), got '" + model + "'");
  }
  c->distortion = DistortionModel::kNone;
  if (d.empty()) return;  // no distortion
  const OpenCvDistCoeffsProblem problem = BrownConradyFromOpenCv(d, &c->brown_conrady);
  if (!problem.ok()) {
    throw InputError(where_coeffs, coeffs_name +
                                       (problem.element < 0 ? std::string(" ")
                                                            : " element " + std::to_string(problem.element + 1) + ": ") +
                                       problem.problem);
  }
  c->distortion = c->brown_conrady.IsZero() ? DistortionModel::kNone : DistortionModel::kBrownConrady;
}

}  // namespace lt

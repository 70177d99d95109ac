// The scanner's camera: intrinsics (OpenCV camera matrix), lens distortion,
// thin lens (defocus) and the radiometry that turns scene radiance into sensor
// irradiance.
//
// Conventions (OpenCV): camera frame x right, y down, z forward; the centre of
// pixel (0, 0) is at image coordinate (0, 0), so the image spans
// [-0.5, width - 0.5] x [-0.5, height - 0.5].
//
// Lens and radiometry. The camera matrix's fx (pixels) times the pixel pitch is
// the image distance v (lens to sensor) of the calibrated camera. Without a
// focus distance the camera is a pinhole geometrically (every ray starts at the
// origin, everything is sharp) but still gathers light through an aperture of
// f-number N with focal length f = v. With focus distance S it is a thin lens
// focused at S: focal length f = v·S/(v + S) (so that 1/f = 1/v + 1/S), aperture
// diameter A = f/N, and rays for one pixel start on the aperture disc (the lens
// plane z = 0) and converge on the plane z = S where the pinhole ray meets it.
// A point at depth D is then blurred into a circle of diameter
//   c = A·f·|D − S| / (D·(S − f))        (on the sensor, metres)
// Irradiance on the sensor for scene radiance L seen through pixel p:
//   E = L · (π A²/4) · cos θ · (dΩ/dA_pixel)
// where θ is the angle of p's chief ray to the optical axis and dΩ/dA_pixel the
// solid angle the pixel sees per unit sensor area. Without distortion this is the
// textbook E = L · π/(4 N_w²) · cos⁴θ with the working f-number N_w = N·v/f
// (= N for a pinhole, N·(1 + magnification) for a lens focused at S). With
// distortion dΩ/dA_pixel follows the distortion's Jacobian. For the fisheye the
// aperture is taken to face the chief ray (its entrance pupil turns with the
// field), so the cos θ factor is dropped.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

#include "sensor/distortion.h"

namespace lt {

struct CameraParams {
  int width = 640;
  int height = 480;
  double fx = 1600.0, fy = 1600.0;  // pixels
  double cx = 319.5, cy = 239.5;    // pixels
  double pixel_pitch_m = 5e-6;      // square pixels
  DistortionModel distortion = DistortionModel::kNone;
  BrownConradyCoeffs brown_conrady;
  KannalaBrandtCoeffs fisheye;
  double f_number = 4.0;                   // > 0
  std::optional<double> focus_distance_m;  // thin lens when set; pinhole geometry otherwise

  // Throws ParamError naming the key ("resolution", "fx", "f_number", ...).
  void Check() const;
};

// A ray from the camera: origin and unit direction in the camera frame.
struct CameraRay {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
};

class Camera {
 public:
  Camera() : Camera(CameraParams{}) {}
  // Checks the parameters and analyses the distortion (throws ParamError,
  // e.g. on "distortion" when it folds inside the image).
  explicit Camera(const CameraParams& params);

  const CameraParams& params() const { return params_; }
  int width() const { return params_.width; }
  int height() const { return params_.height; }
  double fx() const { return params_.fx; }
  double fy() const { return params_.fy; }
  double cx() const { return params_.cx; }
  double cy() const { return params_.cy; }
  double pixel_pitch_m() const { return params_.pixel_pitch_m; }
  double pixel_area_m2() const { return params_.pixel_pitch_m * params_.pixel_pitch_m; }
  DistortionModel distortion_model() const { return distortion_.model(); }
  const LensDistortion& distortion() const { return distortion_; }
  Eigen::Matrix3d K() const;

  // True when the image point lies on the sensor ([-0.5, w - 0.5] x [-0.5, h - 0.5]).
  bool InImage(const Eigen::Vector2d& pixel) const;

  // Pixel of a point in the camera frame; nullopt behind the camera (pinhole
  // models: z <= 0) or outside the distortion's valid domain (see distortion.h).
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& p_in_cam) const;
  // Unit ray through a pixel (z > 0 for pinhole models; a fisheye returns z <= 0
  // beyond 90°); nullopt when no valid ray maps to the pixel to 1e-9 px.
  std::optional<Eigen::Vector3d> Unproject(const Eigen::Vector2d& pixel) const;

  // ---- lens
  bool is_pinhole() const { return !params_.focus_distance_m.has_value(); }
  double f_number() const { return params_.f_number; }
  double image_distance_m() const { return params_.fx * params_.pixel_pitch_m; }  // v
  double focal_length_m() const;          // f (= v for a pinhole)
  double aperture_diameter_m() const { return focal_length_m() / params_.f_number; }
  double working_f_number() const { return params_.f_number * image_distance_m() / focal_length_m(); }
  // Focus distance S (infinity for a pinhole).
  double focus_distance_m() const;
  // Diameter of the circle of confusion on the sensor (metres, and pixels) for a
  // point at depth z = depth_m; 0 for a pinhole.
  double CircleOfConfusionM(double depth_m) const;
  double CircleOfConfusionPx(double depth_m) const { return CircleOfConfusionM(depth_m) / pixel_pitch_m(); }

  // The ray for image point `pixel` (subpixel) and lens sample in [0,1)²
  // (mapped to the aperture disc by the concentric mapping). A pinhole ignores the
  // lens sample. nullopt when the pixel has no valid ray.
  std::optional<CameraRay> GenerateRay(const Eigen::Vector2d& pixel, const Eigen::Vector2d& lens_sample) const;

  // ---- radiometry
  // Solid angle seen by a unit square of image coordinates (1 px²) at `pixel`,
  // in sr per px² (0 when no valid ray).
  double PixelSolidAngle(const Eigen::Vector2d& pixel) const;
  // E/L: sensor irradiance (W/m²) per unit scene radiance (W/(m² sr)) at `pixel`,
  // per the formula above. 0 when the pixel has no valid ray.
  double RadianceToIrradiance(const Eigen::Vector2d& pixel) const;

 private:
  CameraParams params_;
  LensDistortion distortion_;
};

// Maps a uniform sample in [0,1)² to the unit disc (Shirley–Chiu concentric map).
Eigen::Vector2d ConcentricDisk(const Eigen::Vector2d& u);

}  // namespace lt

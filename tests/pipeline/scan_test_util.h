// The synthetic run folders of the scan tests: a distorted camera looks at a
// tilted plane lit by one or three laser sheets; for every image column the
// exact row where each sheet's stripe crosses it is found by bisection on the
// real camera model, and the frame is drawn as a pixel-integrated Gaussian
// around it.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image_io.h"
#include "pipeline/calibration_file.h"
#include "pipeline/demosaic.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan.h"
#include "pipeline/scan_output.h"
#include "sensor/rig.h"

namespace lt::scan_test {

namespace fs = std::filesystem;

inline constexpr double kDeg = M_PI / 180.0;

// Built once: the distortion's domain analysis is costly in sanitizer builds.
inline const Camera& TestCamera() {
  static const Camera camera = [] {
    CameraParams p;
    p.width = 160;
    p.height = 120;
    p.pixel_pitch_m = 19.2e-6;
    p.fx = p.fy = 462.97;
    p.cx = 79.5;
    p.cy = 59.5;
    p.distortion = DistortionModel::kBrownConrady;
    p.brown_conrady = {-0.2, 0.05, 0.001, -0.0005, 0};
    return Camera(p);
  }();
  return camera;
}

// A projector 40 mm beside the camera (+y), aimed at the optical axis 80 mm
// away. Mounted upside down (turned 180 degrees about its beam), its sheet
// numbers run bottom to top in the image instead of top to bottom.
inline LaserProjector TestLaser(int sheets, bool upside_down = false) {
  LaserParams lp;
  lp.sheet_angles_rad = EvenSheetAngles(sheets, 3 * kDeg);
  lp.sheet_power.assign(size_t(sheets), 1.0);
  lp.cam_from_projector = Pose::Identity();
  lp.cam_from_projector.translation() = Eigen::Vector3d(0, 0.04, 0);
  lp.cam_from_projector.linear() =
      upside_down ? (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(-26.565 * kDeg, Eigen::Vector3d::UnitX())).toRotationMatrix()
                  : Eigen::AngleAxisd(26.565 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return LaserProjector(lp);
}

// The object: a plane about 80 mm in front, tilted about both axes.
inline const Plane kObject = Plane::FromPointNormal({0, 0, 0.08}, {0.15, -0.1, 1});

inline std::optional<Eigen::Vector3d> SurfacePoint(const Camera& cam, double u, double v) {
  auto ray = cam.Unproject({u, v});
  if (!ray) return std::nullopt;
  return (-kObject.d / kObject.n.dot(*ray)) * *ray;
}

// The row where the sheet's stripe crosses column u (NaN if it does not).
inline double ExactRow(const Camera& cam, const Plane& sheet, double u) {
  auto g = [&](double v) { return sheet.SignedDistance(*SurfacePoint(cam, u, v)); };
  double a = -0.5, b = cam.height() - 0.5;
  double ga = g(a), gb = g(b);
  if (ga * gb > 0) return std::nan("");
  for (int i = 0; i < 200 && b - a > 1e-12; ++i) {
    double m = 0.5 * (a + b), gm = g(m);
    if ((gm > 0) == (ga > 0)) {
      a = m;
      ga = gm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

inline double Phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

struct SyntheticRun {
  fs::path dir;
  Camera camera = TestCamera();
  std::vector<Plane> sheets;
  Pose world_from_cam = Pose::Identity();
  std::vector<std::vector<double>> rows;  // [sheet][column]: ExactRow at each integer column

  // The exact row of sheet k at column u (points searched along columns have integer u).
  double Row(int k, double u) const {
    const int c = int(u);
    if (double(c) == u && c >= 0 && c < int(rows[size_t(k)].size())) return rows[size_t(k)][size_t(c)];
    return ExactRow(camera, sheets[size_t(k)], u);
  }
};

// Writes a run folder: frame 0 lit by the laser (10-bit DN in a 16-bit PNG),
// frame 1 a bright frame whose image does not exist (a scan must not read it).
// With `mosaic` not kMono, the rig's sensor is a colour one and the frame its
// raw Bayer mosaic of a red laser (R 1.0, G 0.25, B 0.05).
inline SyntheticRun MakeRun(const std::string& name, int n_sheets, bool upside_down = false,
                     ColorFilter mosaic = ColorFilter::kMono, double peak = 1000, double saturation_dn = 1023) {
  SyntheticRun run;
  run.dir = fs::temp_directory_path() / ("lt_scan_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(run.dir);
  fs::create_directories(run.dir / "frames");
  SensorRig rig;
  rig.camera = run.camera;
  rig.lasers.push_back(TestLaser(n_sheets, upside_down));
  for (int k = 0; k < n_sheets; ++k) run.sheets.push_back(rig.lasers[0].SheetPlane(k));
  nlohmann::json rig_json = SensorRigToJson(rig);
  if (mosaic != ColorFilter::kMono) {
    static const char* const kNames[] = {"mono", "rggb", "bggr", "grbg", "gbrg"};
    rig_json["image_sensor"]["color_filter"] = kNames[int(mosaic)];
    // Quantum efficiency in proportion to the stripe's channel gains below.
    rig_json["image_sensor"]["quantum_efficiency"] = {{"wavelength_nm", {650}}, {"r", {0.8}}, {"g", {0.2}}, {"b", {0.04}}};
  }
  std::ofstream(run.dir / "rig.json") << rig_json.dump(2);
  run.world_from_cam.linear() = Eigen::AngleAxisd(3.0, Eigen::Vector3d(0.1, 1, 0.05).normalized()).toRotationMatrix();
  run.world_from_cam.translation() = Eigen::Vector3d(0.3, -0.1, 0.5);

  // Stripe: Gaussian across it with sigma 1.2 px and peak `peak` DN (clipped at
  // saturation_dn), integrated over each pixel along the column, on a black background.
  const double sigma = 1.2, background = 0;
  Image<float> img(run.camera.width(), run.camera.height(), 1, float(background));
  for (const Plane& sheet : run.sheets) {
    run.rows.emplace_back();
    for (int u = 0; u < img.width; ++u) {
      const double vc = ExactRow(run.camera, sheet, u);
      run.rows.back().push_back(vc);
      if (std::isnan(vc)) continue;
      for (int y = 0; y < img.height; ++y) {
        const double mass = Phi((y + 0.5 - vc) / sigma) - Phi((y - 0.5 - vc) / sigma);
        img.At(u, y) += float(peak * sigma * std::sqrt(2 * M_PI) * mass);
      }
    }
  }
  Image<uint16_t> dn(img.width, img.height, 1);
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    dn.pixels[i] = uint16_t(std::lround(std::min(double(img.pixels[i]), saturation_dn)));
  }
  if (mosaic != ColorFilter::kMono) {
    const double gain[3] = {1.0, 0.25, 0.05};
    for (int y = 0; y < dn.height; ++y)
      for (int x = 0; x < dn.width; ++x)
        dn.At(x, y) = uint16_t(std::lround(std::min(img.At(x, y) * gain[FilterChannel(mosaic, x, y)], 1023.0)));
  }
  WriteImage(run.dir / "frames/000000.png", dn);

  nlohmann::json dim = {{"index", 0},
                        {"shutter", {{"laser_on", true}}},
                        {"files", {{"image", "frames/000000.png"}}},
                        {"world_from_cam", PoseToJson(run.world_from_cam)},
                        {"gt_axis", "cols"},
                        {"png_bit_depth", 16},
                        {"bit_depth", 10}};
  if (saturation_dn < 1023) dim["saturation_dn"] = saturation_dn;
  nlohmann::json bright = {{"index", 1}, {"shutter", {{"laser_on", false}}}, {"files", {{"image", "frames/000001.png"}}}};
  std::ofstream(run.dir / "manifest.jsonl") << dim.dump() << "\n" << bright.dump() << "\n";
  return run;
}

// Distance from the triangulated point to the exact one, in units of the
// surface's displacement per pixel along the column (so the tolerance reads in pixels).
inline double ErrorInPixels(const SyntheticRun& run, int sheet, const ScanPoint& p) {
  const double vc = run.Row(sheet, p.pixel.u);
  const Eigen::Vector3d exact = *SurfacePoint(run.camera, p.pixel.u, vc);
  const double per_px = (*SurfacePoint(run.camera, p.pixel.u, vc + 0.5) - *SurfacePoint(run.camera, p.pixel.u, vc - 0.5)).norm();
  return (*p.p_in_cam - exact).norm() / per_px;
}


}  // namespace lt::scan_test

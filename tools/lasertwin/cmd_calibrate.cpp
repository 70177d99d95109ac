// `lasertwin calibrate camera|laser|hand-eye RUN_DIR --out calib.yaml
// [--calib IN.yaml] [--board FILE | --rows R --cols C --square-mm S]
// [--shutter P] [--poses FILE ...] [--bit-depth N]`:
// calibrates one part of the scanner from a calibration session's run folder
// or a capture without a manifest read as scan reads it (pipeline/calib_session.h),
// or the camera from a folder of photographs
// (pipeline/calib_camera_images.h), and writes the calibration file (OpenCV
// YAML, or OpenCV XML for an --out ending in .xml; pipeline/calibration_file.h)
// with that part added to IN.yaml's. Prints the result with its uncertainty,
// and against the run's ground truth (rig.json, scene.json) when the run has one.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "core/error.h"
#include "pipeline/calib_camera_images.h"
#include "pipeline/calib_output.h"
#include "pipeline/calib_session.h"
#include "pipeline/calibration_file.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/stripe_extractor.h"
#include "pipeline/triangulation.h"
#include "tools/lasertwin/calib_camera_arg.h"
#include "tools/lasertwin/calibrate_inputs.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {
namespace {

constexpr double kDeg = M_PI / 180.0;

void CameraStep(const CalibrateArgs& a, CalibrationFile* file) {
  CameraCalibrationOptions o;
  if (a.model == "fisheye") {
    o.model = DistortionModel::kFisheye;
  } else if (a.model == "none") {
    o.model = DistortionModel::kNone;
  } else if (a.model != "brown_conrady") {
    throw InputError("--model", "expected brown_conrady, fisheye or none, got '" + a.model + "'");
  }
  o.fix_k3 = a.fix_k3;
  o.Check();  // before the images are read
  std::string counts;                // "N of M views"
  CameraCalibrationResult c;
  // A folder without a manifest whose bright frames --shutter names is a capture.
  const bool photos = !IsRunFolder(a.run_dir) && a.shutter == "recorded";
  std::optional<SessionRun> run;
  if (photos) {
    if (a.board.empty() && a.rows <= 0 && a.cols <= 0 && a.square_mm <= 0) {
      throw InputError(a.run_dir, "a folder of photographs (no manifest.jsonl): give the board with --rows, --cols "
                                  "and --square-mm (inner corners) or --board FILE");
    }
    const CheckerboardSpec board = Board(a);
    const PhotoCameraResult r = CalibrateCameraFromImages(ListImageFiles(a.run_dir), board, o, {},
                                                          Bayer(a).value_or(ColorFilter::kMono), Warn);
    if (r.one_channel > 0 && a.extraction.bayer.empty()) {
      Warn(a.run_dir + ": " + std::to_string(r.one_channel) + " one-channel image(s) taken as a mono sensor's (--bayer "
           "sets a mosaic)");
    }
    for (const PhotoView& v : r.views) {
      if (!v.detection.ok) Warn(v.image.string() + ": " + v.detection.reason);
    }
    counts = std::to_string(r.used.size()) + " of " + std::to_string(r.views.size()) + " images";
    c = r.calibration;
  } else {
    const CheckerboardSpec board = Board(a);
    run = Session(a, {}, false);
    const SessionCameraResult r = CalibrateSessionCamera(*run, board, o, {}, Warn);
    PrintSkipped(r.views);
    counts = std::to_string(r.used.size()) + " of " + std::to_string(r.views.size()) + " views";
    c = r.calibration;
    if (!c.ok) c.reason += Hint(*run, r.views);
  }
  if (!c.ok) throw InputError(a.run_dir, "camera calibration refused (" + counts + " with the board): " + c.reason);
  if (!c.note.empty()) std::cerr << "lasertwin: note: " << c.note << "\n";
  file->camera = MakeCalibrationFile(&c, nullptr, nullptr).camera;
  if (a.quiet) return;
  // The distortion is determined only where the boards were seen.
  const std::string field = Fmt("  valid within the field the boards observed: corners up to %.1f deg from the "
                                "axis, %.0f px from the principal point; beyond, the distortion is extrapolated\n",
                                c.observed_field_rad / kDeg, c.observed_radius * c.camera.fx);
  if (photos || !run->rig_in_run) {
    std::cout << "camera from " << counts << ", " << c.camera.width << "x" << c.camera.height
              << ": reprojection RMS " << Fmt("%.4f", c.rms_px) << " px\n" << field;
    std::cout << "  param        recovered        std\n";
    for (int i = 0; i < int(c.params.size()); ++i) {
      std::cout << "  " << c.param_names[size_t(i)]
                << std::string(8 - std::min<size_t>(7, c.param_names[size_t(i)].size()), ' ')
                << Fmt("%14.6g  %11.3g", c.params[i], c.param_std[i]) << "\n";
    }
    return;
  }
  const RunRig& rig = run->rig;
  const CameraParams& t = rig.camera.params();
  std::vector<double> truth = {t.fx, t.fy, t.cx, t.cy};
  if (o.model == DistortionModel::kBrownConrady) {
    const auto& k = t.brown_conrady;
    truth.insert(truth.end(), {k.k1, k.k2, k.p1, k.p2, k.k3});
  } else if (o.model == DistortionModel::kFisheye) {
    const auto& k = t.fisheye;
    truth.insert(truth.end(), {k.k1, k.k2, k.k3, k.k4});
  }
  const bool same_model = t.distortion == o.model || t.distortion == DistortionModel::kNone;
  std::cout << "camera from " << counts << ", " << c.camera.width << "x"
            << c.camera.height << ": reprojection RMS " << Fmt("%.4f", c.rms_px) << " px\n" << field;
  std::cout << "  param        recovered        std         true (" << rig.source.filename().string()
            << ")   error   error/std\n";
  for (int i = 0; i < int(c.params.size()); ++i) {
    std::cout << "  " << c.param_names[size_t(i)]
              << std::string(8 - std::min<size_t>(7, c.param_names[size_t(i)].size()), ' ')
              << Fmt("%14.6g  %11.3g", c.params[i], c.param_std[i]);
    if (same_model && i < int(truth.size())) {
      const double e = c.params[i] - truth[size_t(i)];
      std::cout << Fmt("  %14.6g  %+10.3g", truth[size_t(i)], e);
      if (c.param_std[i] > 0) std::cout << Fmt("  %+6.2f", e / c.param_std[i]);
    }
    std::cout << "\n";
  }
}

void LaserStep(const CalibrateArgs& a, CalibrationFile* file) {
  // The dim frames are extracted as scan extracts a run's laser frames.
  const ParsedExtraction x = a.extraction.Parse();
  SessionLaserOptions o;
  o.extraction = x.extraction;
  o.method_from_planes = x.method_from_planes;
  o.transfer_given = x.transfer_given;
  o.plane_id = x.plane_id;
  o.planes = a.planes;
  if (!a.axis.empty()) o.axis = ParseAxis(a.axis, "--axis");
  o.Check();  // before the images are read
  const CheckerboardSpec board = Board(a);
  const SessionRun run = Session(a, *file, true);
  const RunRig& rig = run.rig;
  if (!run.rig_in_run && rig.planes_in_cam.empty() && a.planes <= 0) {
    throw InputError(a.run_dir, "no rig.json, and " + a.calib + " holds no laser planes: give the number of laser "
                                "sheets with --planes N");
  }
  const Camera camera = StepCamera(a, *file, rig);
  const SessionLaserResult r = CalibrateSessionLaser(run, board, camera, o, Warn);
  if (r.axis_from_frame >= 0 && !a.quiet) {
    const bool cols = r.axis == SearchAxis::kCols;
    std::cerr << "stripes searched along the " << (cols ? "columns" : "rows") << " (more stripe points than along the "
              << (cols ? "rows" : "columns") << " on frame " << r.axis_from_frame
              << "; no laser planes known, --axis sets it)\n";
  }
  if (r.mosaic_mean) {
    Warn(r.channel_weights_source + ": colour frames are extracted on the mean of R, G and B, not on the channels "
         "that see the laser");
  } else if (!r.channel_weights_source.empty() && !a.quiet) {
    std::cerr << "colour frames extracted on " << r.channel_weights_source << "\n";
  }
  int used = 0, extracted = 0, stripe_points = 0;
  for (const SessionLaserView& v : r.laser_views) {
    used += v.used;
    extracted += v.pose.ok;  // its dim frame was extracted
    stripe_points += v.stripe_points;
    if (!v.note.empty()) Warn("view " + std::to_string(v.view) + ": " + v.note);
  }
  // As scan says it: no dim frame gave a stripe point.
  if (extracted > 0 && stripe_points == 0) std::cerr << "lasertwin: note: " << NoStripePointsNote(o.extraction) << "\n";
  std::string refused;
  for (const LaserPlaneFit& f : r.fits) {
    if (!f.ok) refused += (refused.empty() ? "" : "; ") + ("plane " + std::to_string(f.plane_id) + ": " + f.reason);
  }
  if (int(r.fits.size()) != r.planes) {
    refused += (refused.empty() ? "" : "; ") + std::to_string(r.fits.size()) + " plane(s) found, " +
               std::to_string(r.planes) + " expected";
  }
  if (!refused.empty()) {
    throw InputError(a.run_dir, "laser plane calibration refused (" + std::to_string(used) + " views with a stripe on "
                                "the board): " + refused + Hint(run, r.views));
  }
  // Plane k of the fit is the k-th stripe in image order; the file numbers the
  // rig's planes (sheets of laser 0 first), in the nominal rig's image order.
  CalibrationFile part = MakeCalibrationFile(nullptr, &r.fits, nullptr);
  std::vector<int> order(r.fits.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = int(k);
  if (rig.planes_in_cam.size() == r.fits.size()) order = PlanesInImageOrder(rig.planes_in_cam, r.axis);
  file->laser_planes.assign(r.fits.size(), Plane{});
  for (size_t k = 0; k < r.fits.size(); ++k) file->laser_planes[size_t(order[k])] = part.laser_planes[k];
  if (a.quiet) return;
  std::cout << "laser planes from " << used << " views (camera frame, n.p + d = 0):\n";
  for (size_t k = 0; k < r.fits.size(); ++k) {
    const LaserPlaneFit& f = r.fits[k];
    std::cout << "  plane " << order[k] << ": n = (" << Fmt("%.6f, %.6f, %.6f", f.plane.n.x(), f.plane.n.y(), f.plane.n.z())
              << Fmt("), d = %.4f mm; %.0f of %.0f points inliers, RMS %.2f um", f.plane.d * 1e3, double(f.inliers), double(f.points),
                     f.residual_rms_m * 1e6)
              << Fmt("; std: normal %.4f deg, offset %.4f mm\n", f.normal_std_rad / kDeg, f.offset_std_m * 1e3);
    if (run.rig_in_run && rig.planes_in_cam.size() == r.fits.size()) {
      const PlaneError e = ComparePlanes(f.plane, rig.planes_in_cam[size_t(order[k])]);
      std::cout << "           against the true plane: normal " << Fmt("%.4f", e.normal_angle_rad / kDeg)
                << " deg, offset " << Fmt("%.4f", e.offset_m * 1e3) << " mm\n";
    }
  }
}

void HandEyeStep(const CalibrateArgs& a, CalibrationFile* file) {
  if (!IsRunFolder(a.run_dir) && a.pose_args.poses.empty()) {
    throw InputError(a.run_dir, "a capture without manifest.jsonl has no robot poses: give the tool's poses "
                                "(world_from_tool) with --poses FILE");
  }
  const CheckerboardSpec board = Board(a);
  const SessionRun run = Session(a, *file, true);
  const Camera camera = StepCamera(a, *file, run.rig);
  const SessionHandEyeResult r = CalibrateSessionHandEye(run, board, camera, {}, {}, Warn);
  for (const auto& n : r.notes) Warn(n);
  const HandEyeResult& h = r.hand_eye;
  if (!h.ok) {
    throw InputError(a.run_dir, "hand-eye calibration refused (" + std::to_string(r.used.size()) + " of " +
                                    std::to_string(r.views.size()) + " views usable): " + h.reason +
                                    Hint(run, r.views));
  }
  file->tool_from_cam = MakeCalibrationFile(nullptr, nullptr, &h).tool_from_cam;
  if (a.quiet) return;
  const Eigen::Vector3d t = h.tool_from_cam.translation() * 1e3;
  const Eigen::Vector3d rv = RotationLog(h.tool_from_cam.linear()) / kDeg;
  std::cout << "tool_from_cam from " << r.used.size() << " views: translation (" << Fmt("%.4f, %.4f, %.4f", t.x(), t.y(), t.z())
            << ") mm, rotation vector (" << Fmt("%.4f, %.4f, %.4f", rv.x(), rv.y(), rv.z()) << ") deg\n"
            << "  std: rotation " << Fmt("%.4f", h.rotation_std_rad / kDeg) << " deg, translation "
            << Fmt("%.4f", h.translation_std_m * 1e3) << " mm; reprojection RMS " << Fmt("%.4f", h.reprojection_rms_px)
            << " px, variance factor " << Fmt("%.3f", h.variance_factor) << "\n";
  if (!std::filesystem::exists(std::filesystem::path(a.run_dir) / "scene.json")) return;
  const SessionTruth truth = ReadSessionTruth(a.run_dir);
  if (truth.tool_from_cam) {
    const PoseError e = ComparePoses(h.tool_from_cam, *truth.tool_from_cam);
    std::cout << "  against the true tool_from_cam (scene.json): rotation " << Fmt("%.4f", e.rotation_rad / kDeg)
              << " deg, translation " << Fmt("%.4f", e.translation_m * 1e3) << " mm\n";
  }
}

void Run(const CalibrateArgs& a) {
  RequireOutputFolder("--out", a.out);
  CalibrationFileFormat(a.out);  // an unknown extension is refused before the work
  CalibrationFile file = InputFile(a);
  file.ignored_keys.clear();
  if (!a.pose_args.poses.empty() && a.step != "hand-eye") {
    Warn("--poses: the " + a.step + " step uses no robot poses");
  }
  // --bayer is every step's (the bright frames' mosaic).
  const std::string extraction = a.extraction.Given("--bayer");
  if (!extraction.empty() && a.step != "laser") {
    Warn(extraction + ": the " + a.step + " step extracts no laser stripe (the laser step's options)");
  }
  if (a.step == "camera") {
    CameraStep(a, &file);
  } else if (a.step == "laser") {
    LaserStep(a, &file);
  } else {
    HandEyeStep(a, &file);
  }
  WriteCalibrationFile(a.out, file);
  if (!a.quiet) std::cerr << "wrote " << a.out << "\n";
}

void Add(CLI::App& app) {
  auto args = std::make_shared<CalibrateArgs>();
  auto* cmd = app.add_subcommand("calibrate",
                                 "Calibrate the camera, laser planes or hand-eye pose from a calibration session run or capture");
  cmd->add_option("STEP", args->step, "camera | laser | hand-eye")
      ->required()
      ->check(CLI::IsMember({"camera", "laser", "hand-eye"}));
  cmd->add_option("RUN_DIR", args->run_dir,
                  "Run folder of a calibration session (bright/dim frame pairs), or a capture without manifest.jsonl "
                  "(images in file name order, directly in it or in its frames/; --shutter says which are bright); "
                  "camera without --shutter: a folder of photographs of the board (every image file; give the board)")
      ->required();
  cmd->add_option("--out", args->out, "Calibration file to write: OpenCV YAML (.yaml, .yml) or OpenCV XML (.xml)")
      ->required();
  cmd->add_option("--calib", args->calib,
                  "Calibration file to start from (its camera is used by the laser and hand-eye steps; a folder "
                  "without rig.json needs it)");
  DeclareCalibCamera(cmd, &args->calib_camera);
  cmd->add_option("--board", args->board,
                  "Board layout (JSON: rows, cols, square_mm); default: checkerboard.json of the session");
  cmd->add_option("--rows", args->rows, "Inner corners down a column (instead of --board)");
  cmd->add_option("--cols", args->cols, "Inner corners along a row");
  cmd->add_option("--square-mm", args->square_mm, "Square size (mm)");
  cmd->add_option("--model", args->model, "camera: brown_conrady | fisheye | none")->capture_default_str();
  cmd->add_flag("--fix-k3", args->fix_k3, "camera: hold k3 at 0");
  cmd->add_option("--planes", args->planes, "laser: number of laser sheets (default: the run's rig, else --calib's laser planes)");
  cmd->add_option("--shutter", args->shutter,
                  "recorded | alternate | alternate-bright-first: which frames are bright (the board) and which dim "
                  "(the laser): the manifest's shutter keys, or alternate frames, the first a dim one or a bright one")
      ->capture_default_str();
  args->pose_args.Declare(cmd,
                          "hand-eye: the robot tool's poses (world_from_tool), one per frame in frame order, one per "
                          "bright frame, or with times matched to images named by their time (the forms of scan "
                          "--poses, docs/pipeline.md); replace the manifest's");
  cmd->add_option("--bit-depth", args->bit_depth,
                  "The image sensor's ADC bits (1..16): a 16-bit image of a 12-bit camera reads up to 4095 (default: "
                  "the manifest's bit_depth, rig.json's)");
  cmd->add_option("--axis", args->axis,
                  "laser: rows | cols, the stripe search (default: from the laser planes of the rig or --calib, else "
                  "the axis finding more stripe points on the first dim frame)");
  // laser: the dim frames' stripe extraction, with scan's options and defaults.
  args->extraction.Declare(cmd);
  cmd->add_flag("--quiet", args->quiet, "Print nothing but warnings");
  cmd->callback([args] { Run(*args); });
}

LT_REGISTER_COMMAND("calibrate", Add);

}  // namespace
}  // namespace lt::cli

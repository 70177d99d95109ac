// `lasertwin scan RUN_DIR [--method ...] [--calib FILE] [--axis rows|cols]
// [--frames A:B] ...`: extracts, identifies and triangulates the stripe points
// of every laser frame of a run folder; writes RUN_DIR/centers/NNNNNN.csv and
// RUN_DIR/cloud.ply (docs/pipeline.md).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/frame_range.h"
#include "core/text_fields.h"
#include "pipeline/scan.h"
#include "pipeline/stripe_extractor.h"
#include "tools/lasertwin/calib_camera_arg.h"
#include "tools/lasertwin/command.h"
#include "tools/lasertwin/extraction_args.h"
#include "tools/lasertwin/pose_file_args.h"

namespace lt::cli {
namespace {

struct ScanArgs {
  std::string run_dir;
  ExtractionArgs extraction;  // --method, --threshold, ..., --bayer, --roi; plane identification
  std::string axis;
  std::string calib;
  std::string calib_camera;  // --calib-camera
  std::string frames;
  PoseFileArgs pose_args;  // --poses, --pose-units, --pose-order, --image-time-offset
  std::string depth_range;  // MIN_MM:MAX_MM
  std::string shutter = "recorded";
  bool quiet = false;
  ScanOptions options;
};

void Run(ScanArgs& a) {
  ScanOptions& o = a.options;
  const ParsedExtraction x = a.extraction.Parse();
  o.extraction = x.extraction;
  o.method_from_planes = x.method_from_planes;
  o.transfer_given = x.transfer_given;
  o.color_filter = x.color_filter;
  o.plane_id = x.plane_id;
  if (!a.axis.empty()) o.axis = ParseAxis(a.axis, "--axis");
  if (!a.calib.empty()) o.calibration = a.calib;
  o.calibration_file = ParseCalibCamera(a.calib, a.calib_camera);
  if (!a.depth_range.empty()) o.depth_range = ParseDepthRange(a.depth_range, "--depth-range");
  if (!a.pose_args.poses.empty()) o.poses = a.pose_args.poses;
  o.pose_file = a.pose_args.Parse();
  o.shutter = ParseShutterPattern(a.shutter, "--shutter");
  if (!a.frames.empty()) {
    const FrameRange r = FrameRange::Parse(a.frames);
    o.frames_begin = r.begin, o.frames_end = r.EndOrMinusOne();
  }
  ScanSummary s = ScanRun(a.run_dir, o, [](const std::string& w) { std::cerr << "lasertwin: warning: " << w << "\n"; });
  // Points lost to the width checks, or none at all, are said even with --quiet.
  for (const std::string& note : WidthRejectionNotes(s.width_rejected, o.extraction)) {
    std::cerr << "lasertwin: note: " << note << "\n";
  }
  if (s.stats.points == 0) std::cerr << "lasertwin: note: " << NoStripePointsNote(o.extraction) << "\n";
  if (s.saturated_points > 0) {
    std::cerr << "lasertwin: note: " << s.saturated_points << " of " << s.stats.points
              << " stripe points lie on saturated pixels: a clipped stripe's centre is less certain; lower the "
                 "exposure or the laser power\n";
  }
  if (a.quiet) return;
  const TriangulationStats& st = s.stats;
  if (s.frames_from_listing) {
    std::cerr << "frames: the " << s.laser_frames + s.other_frames << " image files of " << s.frames_source.string()
              << " in file name order (no manifest.jsonl)\n";
  }
  std::cerr << "scanned " << s.laser_frames << " laser frame" << (s.laser_frames == 1 ? "" : "s");
  if (s.other_frames > 0) std::cerr << " (" << s.other_frames << " without laser light skipped)";
  std::cerr << ": " << st.points << " stripe points, " << s.triangulated << " triangulated";
  std::string rejected;
  auto add = [&](int n, const char* what) {
    if (n > 0) rejected += (rejected.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  };
  add(st.no_plane, "without plane");
  add(st.no_ray, "without camera ray");
  add(st.grazing, "grazing");
  add(st.behind, "behind the camera");
  if (!rejected.empty()) std::cerr << " (" << rejected << ")";
  std::cerr << "; " << s.planes << " laser plane" << (s.planes == 1 ? "" : "s") << " from " << s.plane_source.string()
            << "; method " << MethodName(s.method) << (o.method_from_planes && s.planes > 1 ? " (several laser planes)" : "")
            << "\n";
  if (!s.channel_weights.empty()) std::cerr << "colour frames extracted on " << s.channel_weights_source << "\n";
  std::vector<double> widths;
  for (const ScanFrameSummary& f : s.frames) {
    if (!std::isnan(f.steger_width_px)) widths.push_back(f.steger_width_px);
  }
  if (!widths.empty()) {
    std::sort(widths.begin(), widths.end());
    auto px = [](double w) {
      std::ostringstream os;
      os << std::fixed << std::setprecision(1) << w;
      return os.str();
    };
    std::cerr << "steger: expected stripe width " << px(widths[widths.size() / 2]) << " px";
    if (widths.front() != widths.back()) {
      std::cerr << " (median of the frames; " << px(widths.front()) << " to " << px(widths.back()) << ")";
    }
    std::cerr << (std::isnan(o.extraction.expected_width) ? ", measured on each frame (--width fixes it)\n"
                                                           : ", from --width\n");
  }
  std::vector<const NoiseThreshold*> thresholds;  // --threshold auto: each frame's
  for (const ScanFrameSummary& f : s.frames) {
    if (f.noise_threshold) thresholds.push_back(&*f.noise_threshold);
  }
  if (!thresholds.empty()) {
    std::sort(thresholds.begin(), thresholds.end(),
              [](const NoiseThreshold* a, const NoiseThreshold* b) { return a->threshold < b->threshold; });
    const NoiseThreshold& mid = *thresholds[thresholds.size() / 2];
    std::cerr << "threshold auto: " << DescribeNoiseThreshold(mid);
    if (thresholds.size() > 1) {
      std::ostringstream range;
      range << std::setprecision(4) << thresholds.front()->threshold << " to " << thresholds.back()->threshold;
      std::cerr << " on the median frame; " << range.str() << " over " << thresholds.size() << " frames";
    }
    const auto varied = std::count_if(thresholds.begin(), thresholds.end(), [](const NoiseThreshold* t) {
      return t->from == NoiseThreshold::From::kSpread;
    });
    if (varied > 0 && thresholds.size() > 1) {
      std::cerr << "; " << varied << " frame" << (varied == 1 ? "" : "s")
                << " set by the background's spread (ambient light: --background local)";
    }
    std::cerr << "\n";
  }
  if (s.frames_by_edge_chains > 0) {
    std::cerr << "planes numbered by the edge chains in " << s.frames_by_edge_chains << " frame"
              << (s.frames_by_edge_chains == 1 ? "" : "s") << " (no search line met all the stripes)\n";
  }
  if (s.unidentified_segments > 0) {
    std::cerr << s.unidentified_segments << " stripe segment" << (s.unidentified_segments == 1 ? "" : "s")
              << " left without a plane (their place among the stripes is not certain)\n";
  }
  if (s.coloured) {
    const ColourStats& c = s.colour;
    std::cerr << "colour from " << c.bright_frames << " bright frame" << (c.bright_frames == 1 ? "" : "s") << ": "
              << c.coloured << " of " << c.points << " points coloured; " << c.contaminated
              << " contaminated by laser light (" << std::fixed << std::setprecision(1) << (c.coloured > 0 ? 100.0 * c.contaminated / c.coloured : 0.0) << std::defaultfloat
              << "% of the coloured, " << (c.from_radiance ? "from the radiance images" : "from the lit fractions")
              << ")\n";
  }
  std::cerr << "wrote " << a.run_dir << "/centers/ and " << a.run_dir << "/cloud.ply ("
            << (s.world_frame ? "world frame, poses " + s.pose_source : std::string("camera frame")) << ")\n";
}

void Add(CLI::App& app) {
  auto args = std::make_shared<ScanArgs>();
  auto* cmd = app.add_subcommand(
      "scan", "Extract, identify and triangulate the laser frames of a run folder (centers/*.csv, cloud.ply)");
  cmd->add_option("RUN_DIR", args->run_dir,
                  "Run folder (from lasertwin render, or a capture with the same layout), or a folder of images "
                  "without manifest.jsonl (frames in file name order, directly in it or in its frames/)")
      ->required();
  cmd->add_option("--calib", args->calib,
                  "Calibration file (OpenCV YAML or XML, as lasertwin calibrate writes): its laser planes (and camera, "
                  "and hand-eye pose tool_from_cam with the run's world_from_tool) replace the run's ground truth");
  DeclareCalibCamera(cmd, &args->calib_camera);
  cmd->add_option("--axis", args->axis, "rows | cols (default: the manifest's gt_axis, else from the laser planes)");
  cmd->add_option("--frames", args->frames, "Frames to scan: A:B (A inclusive, B exclusive), A:, :B or N");
  args->pose_args.Declare(cmd,
                          "Pose file, one pose per frame in frame order, or with times matched to images named by "
                          "their time (CSV with a header, TUM, 7-number, 3x4 or 4x4 rows; docs/pipeline.md): the tool's poses "
                          "with --calib's tool_from_cam, else the camera's (world_from_cam)");
  cmd->add_option("--shutter", args->shutter,
                  "recorded | alternate | alternate-bright-first: which frames the laser lit: the manifest's shutter "
                  "keys (none, or no manifest: every frame), or alternate frames, the first a laser (dim) frame or a "
                  "bright one (colour from the bright ones)")
      ->capture_default_str();
  cmd->add_option("--bit-depth", args->options.bit_depth,
                  "The image sensor's ADC bits (1..16): a 16-bit image of a 12-bit camera reads up to 4095 (default: "
                  "the manifest's bit_depth, rig.json's)");
  args->extraction.Declare(cmd);
  cmd->add_option("--depth-range", args->depth_range,
                  "Plane identification: the scanner's working range MIN_MM:MAX_MM (camera z), e.g. 60:120: with "
                  "several sheets, stripes are numbered by the sheets' order at these depths only, and points outside "
                  "it keep no plane");
  cmd->add_option("--min-ray-angle-deg", args->options.triangulation.min_ray_angle_deg,
                  "Reject rays closer than this to the laser plane (degrees)")
      ->capture_default_str();
  cmd->add_option("--contamination-ratio", args->options.colour.contamination_ratio,
                  "A bright-frame sample is contaminated when its laser radiance is at least this fraction of its "
                  "broadband radiance")
      ->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "No summary on stderr");
  cmd->callback([args] { Run(*args); });
}

}  // namespace

LT_REGISTER_COMMAND("scan", Add);

}  // namespace lt::cli

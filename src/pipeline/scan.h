// Scanning a run folder (`lasertwin scan`, docs/pipeline.md): for every laser
// frame of the run, extract the stripe centres, identify their laser planes and
// triangulate them; write RUN/centers/NNNNNN.csv per frame and RUN/cloud.ply
// (pipeline/scan_output.h), coloured from the run's bright frames when it has
// them (pipeline/colorize.h) and labelled with the ground-truth instance ids when
// it has ground truth. Every file is written atomically; cloud.ply is
// written last, only when every frame was scanned, and missing images are
// reported before anything is written.
#pragma once

#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/auto_threshold.h"
#include "pipeline/calibration_file.h"
#include "pipeline/capture_folder.h"
#include "pipeline/colorize.h"
#include "pipeline/extraction_options.h"
#include "pipeline/plane_id_sheets.h"
#include "pipeline/plane_identification.h"
#include "pipeline/pose_file.h"
#include "pipeline/triangulation.h"

namespace lt {

struct ScanOptions {
  // Extraction as in `lasertwin extract`, with three run-aware defaults:
  //   threshold kAuto: 10% of the frame's full scale, from its bit depth (a
  //     16-bit PNG holding 10-bit raw DN has full scale 1023, not 65535),
  //     times the channel weights' WeightedFullScale() (threshold_mode
  //     kNoise, --threshold auto: each frame's own, pipeline/auto_threshold.h);
  //   background kAuto (NaN here): the image sensor's black level (rig.json),
  //     times the weights' WeightedLevel();
  //   colour frames (a Bayer mosaic or 3 channels) without `channel` or
  //     `channel_weights`: the weights matched to the rig's lasers
  //     (pipeline/channel_weights.h), else (no wavelength or quantum
  //     efficiency in the rig, warned) a mosaic's mean of R, G, B.
  // `axis` is ignored: see `axis` below.
  ExtractionOptions extraction = DefaultExtraction();
  // The method was not chosen (`--method` absent): with several laser planes
  // the scan takes multicom, which finds every stripe on a search line (com
  // and max find one, so N-1 stripes would be lost), else extraction.method.
  bool method_from_planes = false;
  // `--transfer` was given (even linear): a frame file's tag saying its values
  // encode light by a curve (sRGB, gAMA, ICC) is then not warned about.
  bool transfer_given = false;
  // Search axis; unset: the manifest's gt_axis of each frame, else the axis
  // the laser planes' stripes call for (StripeAxis).
  std::optional<SearchAxis> axis;
  // Plane identification (multi-line projectors); `axis` and a too-small
  // edge_margin are set per frame.
  PlaneIdOptions plane_id;
  // The scanner's working range (`--depth-range`, camera z): with several
  // laser planes, only the sheets' orders at these depths number the stripes,
  // and a point that would lie outside it keeps no plane
  // (pipeline/plane_id_sheets.h). Unset: the calibration file's
  // depth_min_mm / depth_max_mm, else 1 mm to 1 km. Never taken from the
  // run's ground truth.
  std::optional<DepthRange> depth_range;
  TriangulationOptions triangulation;
  // Calibration file (pipeline/calibration_file.h): its laser planes replace
  // the run's ground-truth planes, its camera (when present) the run's camera,
  // and its hand-eye pose (when present) with the run's tool poses the
  // manifest's camera poses.
  std::optional<std::filesystem::path> calibration;
  CalibrationFileOptions calibration_file;  // which camera of a file of several (--calib-camera)
  // The raw frames' colour filter mosaic (`--bayer`); unset: rig.json's
  // color_filter (mono for a rig taken from a calibration file).
  std::optional<ColorFilter> color_filter;
  // The image sensor's ADC bits (1..16; 0: rig.json's, else unknown): sets
  // rig.json's and gives frames without a manifest bit_depth (a capture
  // without a manifest: all frames) theirs.
  int bit_depth = 0;
  // A pose file (pipeline/pose_file.h): one pose per frame of the run, in frame
  // order; the tool's (world_from_tool) when the calibration file has
  // tool_from_cam, else the camera's (world_from_cam). It replaces the manifest's.
  std::optional<std::filesystem::path> poses;
  PoseFileOptions pose_file;
  // Which frames are laser frames: the manifest's shutter keys (none: all), or
  // alternating by position (a capture without a manifest); see capture_folder.h.
  ShutterPattern shutter = ShutterPattern::kRecorded;
  // Frames [frames_begin, frames_end) of the manifest (by index); -1: to the end.
  int frames_begin = 0;
  int frames_end = -1;
  // Colour from bright frames and the laser contamination test (pipeline/colorize.h).
  ColourOptions colour;

  static ExtractionOptions DefaultExtraction() {
    ExtractionOptions o;
    o.background = ExtractionOptions::kAuto;
    return o;
  }
  void Check() const;  // throws lt::InputError naming the option
};

struct ScanFrameSummary {
  int index = 0;
  TriangulationStats stats;
  bool identified = true;  // plane identification succeeded (always with one plane)
  std::string identification_error;
  bool by_edge_chains = false;    // numbered by the edge chains (the stripes' order could not decide)
  int unidentified_segments = 0;  // stripe segments left without a plane
  // steger: the expected stripe width (FWHM across the stripe, px) the frame
  // was extracted with: --width, or the one measured on the frame
  // (StripeExtractor::resolved_options()); NaN for the other methods.
  double steger_width_px = std::numeric_limits<double>::quiet_NaN();
  // --threshold auto: the frame's threshold and how it was set
  // (StripeExtractor::last_noise_threshold()); unset with a fixed threshold.
  std::optional<NoiseThreshold> noise_threshold;
};

struct ScanSummary {
  int laser_frames = 0;    // frames scanned
  int other_frames = 0;    // frames in range without laser light (bright frames), skipped
  int points = 0;          // stripe points
  int triangulated = 0;    // points in the cloud
  WidthRejections width_rejected;  // candidate peaks dropped for their width, all frames
  int saturated_points = 0;         // stripe points within one pixel of a saturated pixel (RunFrame::SaturationLevel)
  TriangulationStats stats;  // summed over frames
  bool world_frame = true;   // cloud.ply is in the world frame (every frame had a pose)
  int planes = 0;
  ExtractionMethod method = ExtractionMethod::kCom;  // the method used
  int frames_by_edge_chains = 0;   // frames the edge chains numbered (pipeline/plane_identification.h)
  int unidentified_segments = 0;   // stripe segments left without a plane, all frames
  std::filesystem::path plane_source;  // rig.json, scene.json or the calibration file
  // The camera poses of the cloud: the manifest's world_from_cam, or, when the
  // calibration file has tool_from_cam and the run has tool poses,
  // world_from_tool · tool_from_cam (docs/pipeline.md).
  std::string pose_source = "world_from_cam";
  // Where the frames came from: RUN/manifest.jsonl, or (a capture without a
  // manifest) the folder of the images, listed in natural order.
  std::filesystem::path frames_source;
  bool frames_from_listing = false;
  std::vector<ScanFrameSummary> frames;
  // Colour (cloud in the world frame and the run has bright frames with poses):
  // points coloured and contaminated by laser light (pipeline/colorize.h).
  bool coloured = false;
  ColourStats colour;
  // Colour frames scanned without --channel or --weights: the R, G, B weights
  // matched to the rig's lasers (pipeline/channel_weights.h) and how they were
  // found; empty when the rig could not say (then the mean of R, G, B, warned once).
  std::vector<double> channel_weights;
  std::string channel_weights_source;
};

// Scans a run folder. Warnings (plane identification failed on a frame,
// ignored calibration keys, missing poses) go to `warn`. Bad input throws
// lt::InputError naming the file and place: missing run folder or manifest, a
// corrupt manifest line, a missing or unreadable image, an image whose size is
// not the camera's, an unreadable calibration file, a run without laser frames.
ScanSummary ScanRun(const std::filesystem::path& run_dir, const ScanOptions& options,
                    const std::function<void(const std::string&)>& warn = {});

// "centers/000012.csv"
std::string ScanCentersName(int index);

}  // namespace lt

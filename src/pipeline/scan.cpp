#include "pipeline/scan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <type_traits>
#include <map>
#include <memory>
#include <tuple>

#include "core/error.h"
#include "core/text_fields.h"
#include "core/image_io.h"
#include "pipeline/calibration_file.h"
#include "pipeline/capture_folder.h"
#include "pipeline/channel_weights.h"
#include "pipeline/colorize.h"
#include "pipeline/frame_extraction.h"
#include "pipeline/frame_image_reader.h"
#include "pipeline/image_file_facts.h"
#include "pipeline/plane_id_sheets.h"
#include "pipeline/scan_cloud.h"
#include "pipeline/scan_poses.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan_output.h"
#include "pipeline/stripe_extractor.h"

namespace lt {

namespace fs = std::filesystem;

namespace {

// Whether the image reaches `level` (any channel) within one pixel of p.
bool OnSaturatedPixels(const AnyImage& image, const StripePoint& p, double level) {
  return std::visit(
      [&](const auto& im) {
        const long cx = std::lround(p.u), cy = std::lround(p.v);
        for (long y = std::max(0L, cy - 1); y <= std::min(long(im.height) - 1, cy + 1); ++y)
          for (long x = std::max(0L, cx - 1); x <= std::min(long(im.width) - 1, cx + 1); ++x)
            for (int c = 0; c < im.channels; ++c)
              if (double(im.At(int(x), int(y), c)) >= level) return true;
        return false;
      },
      image);
}

// Whether most samples of a one-channel image reach `level`: a flood-lit frame,
// not a laser stripe on a dark scene.
bool MostlyAbove(const AnyImage& image, double level) {
  return std::visit(
      [&](const auto& im) {
        if (im.channels != 1 || im.pixels.empty()) return false;
        size_t above = 0;
        for (const auto v : im.pixels) above += double(v) >= level;
        return 2 * above > im.pixels.size();
      },
      image);
}

// The largest sample of an image.
double Brightest(const AnyImage& image) {
  return std::visit(
      [](const auto& im) {
        double m = -std::numeric_limits<double>::infinity();
        for (const auto v : im.pixels) m = std::max(m, double(v));
        return m;
      },
      image);
}

// Extractors by (threshold, background, axis, mosaic, colour weights): a run
// normally needs one.
class ExtractorCache {
 public:
  StripeExtractor& Get(const ExtractionOptions& o) {
    auto key = std::make_tuple(o.threshold, o.background, int(o.axis), int(o.bayer), o.channel_weights);
    auto it = cache_.find(key);
    if (it != cache_.end()) return *it->second;
    return *cache_.emplace(key, std::make_unique<StripeExtractor>(o)).first->second;
  }

 private:
  std::map<std::tuple<double, double, int, int, std::vector<double>>, std::unique_ptr<StripeExtractor>> cache_;
};

}  // namespace

std::string ScanCentersName(int index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "centers/%06d.csv", index);
  return buf;
}

void ScanOptions::Check() const {
  ExtractionOptions e = extraction;
  if (std::isnan(e.background)) e.background = 0;
  e.Check();
  plane_id.Check();
  triangulation.Check();
  colour.Check();
  if (depth_range) depth_range->Check("--depth-range");
  if (frames_begin < 0) throw InputError("option frames", "the first frame must be >= 0");
  if (frames_end >= 0 && frames_end <= frames_begin) throw InputError("option frames", "the frame range is empty");
  if (bit_depth < 0 || bit_depth > 16) throw InputError("--bit-depth", "must be 1..16, got " + std::to_string(bit_depth));
}

ScanSummary ScanRun(const fs::path& run_dir, const ScanOptions& options,
                    const std::function<void(const std::string&)>& warn_fn) {
  options.Check();
  auto warn = [&](const std::string& message) {
    if (warn_fn) warn_fn(message);
  };
  ScanFrames listed = ReadScanFrames(run_dir);
  std::vector<RunFrame>& frames = listed.frames;
  if (frames.empty()) throw InputError(listed.source.string(), "holds no frame (expected one JSON object per line)");
  std::optional<CalibrationFile> cal_file;
  if (options.calibration) {
    cal_file = ReadCalibrationFile(*options.calibration, options.calibration_file);
    // Its ignored keys and the readers' notes (another tool's file), as calibrate prints them.
    for (const std::string& w : CalibrationFileWarnings(*cal_file, options.calibration->string(), "ignored")) warn(w);
  }
  // The working range: --depth-range, else the calibration file's.
  const std::optional<DepthRange> depth_range = options.depth_range ? options.depth_range
                                                : cal_file                ? cal_file->depth_range
                                                                          : std::nullopt;
  ApplyShutterPattern(options.shutter, &frames);
  ScanSummary summary;
  summary.frames_source = listed.source;
  summary.frames_from_listing = listed.from_listing;
  summary.pose_source = ResolveScanPoses(options.poses, options.pose_file,
                                         cal_file ? cal_file->tool_from_cam : std::nullopt, options.calibration,
                                         listed.source.string(), &frames, warn);
  // A real capture may have no rig.json: the calibration file's camera is the camera.
  const bool rig_from_calibration = cal_file && cal_file->camera && !HasRunRig(run_dir);
  RunRig rig;
  if (!rig_from_calibration) {
    rig = ReadRunRig(run_dir);
  } else {
    rig.camera = cal_file->MakeCamera(CameraParams{}, options.calibration->string());
    rig.source = *options.calibration;
    NoRigAssumptions assumed;
    assumed.camera_source = rig.source.string();
    assumed.black_level_zero = std::isnan(options.extraction.background);
    assumed.mono = !options.color_filter;
    assumed.bit_depth = options.bit_depth > 0     ? "--bit-depth's"
                        : listed.from_listing     ? "the image's (--bit-depth sets it)"
                                                  : "the manifest's bit_depth or the image's";
    warn(NoRigWarning(run_dir.string(), assumed));
  }
  if (options.color_filter) rig.color_filter = *options.color_filter;
  if (options.bit_depth > 0) rig.bit_depth = options.bit_depth;
  // A manifest line without bit_depth: the image sensor's (threshold, saturation, colour).
  for (RunFrame& f : frames) {
    if (f.bit_depth <= 0) f.bit_depth = rig.bit_depth;
  }
  Camera camera = rig.camera;
  std::vector<Plane> planes = rig.planes_in_cam;
  summary.plane_source = rig.source;
  if (cal_file) {
    const fs::path& path = *options.calibration;
    const CalibrationFile& cal = *cal_file;
    if (cal.laser_planes.empty()) throw InputError(path.string(), "holds no laser_planes (needed to triangulate)");
    if (cal.camera && (cal.camera->width != camera.width() || cal.camera->height != camera.height())) {
      throw InputError(path.string(), "the calibrated camera is " + SizeText(cal.camera->width, cal.camera->height) +
                                          " but the run's camera (" + rig.source.string() + ") is " +
                                          SizeText(camera.width(), camera.height()));
    }
    camera = cal.MakeCamera(camera.params(), path.string());
    if (!rig_from_calibration && int(cal.laser_planes.size()) != int(planes.size())) {
      warn(path.string() + ": holds " + std::to_string(cal.laser_planes.size()) + " laser plane(s), the run's rig " +
           std::to_string(planes.size()));
    }
    planes = cal.laser_planes;
    summary.plane_source = path;
  }
  listed.CheckSize(camera.width(), camera.height(), summary.plane_source.string());
  if (planes.empty()) throw InputError(rig.source.string(), "the rig has no laser plane: nothing to triangulate");
  summary.planes = int(planes.size());
  const Triangulator triangulator(camera, planes, options.triangulation);
  const SearchAxis planes_axis = StripeAxis(planes);
  ExtractionMethod method = options.extraction.method;
  if (options.method_from_planes && planes.size() > 1 && FindsOneStripePerLine(method)) {
    method = ExtractionMethod::kMultiCom;
  }
  summary.method = method;
  if (planes.size() > 1 && FindsOneStripePerLine(method)) {
    warn(std::string(MethodName(method)) + " finds one stripe per search line, but there are " +
         std::to_string(planes.size()) + " laser planes: use --method multicom or steger to see every stripe");
  }
  std::map<int, SheetsOfRanks> sheets_of_ranks;  // the planes of identification's ranks, by axis
  bool warned_uncertain_sheet = false;

  // Missing images are reported before anything is written.
  auto selected = [&](const RunFrame& f) {
    return f.index >= options.frames_begin && (options.frames_end < 0 || f.index < options.frames_end);
  };
  for (const RunFrame& frame : frames) {
    if (selected(frame) && frame.IsLaserFrame() && !fs::exists(frame.image)) {
      throw InputError(frame.image.string(),
                       "no such file (frame " + std::to_string(frame.index) + ", " + frame.where + ")");
    }
  }

  ExtractorCache extractors;
  const LaserChannelWeights matched = MatchedChannelWeights(rig);
  bool warned_colour_default = false;
  bool warned_unknown_depth = false;
  bool warned_above_depth = false;
  ImageFileWarner file_warnings(warn, "frame");  // each once a scan, counted for the other frames
  const bool warn_transfer_tags = !options.transfer_given && options.extraction.transfer == Transfer::kLinear;
  std::vector<int> flooded;  // frames without shutter keys, mostly above the threshold
  std::vector<PendingPoint> pending;
  bool all_posed = true, any_posed = false, all_labelled = true;
  std::error_code ec;
  for (const RunFrame& listed : frames) {
    if (!selected(listed)) continue;
    RunFrame frame = listed;  // its bit depth may come from its file (below)
    if (!frame.IsLaserFrame()) {
      ++summary.other_frames;
      fs::remove(run_dir / ScanCentersName(frame.index), ec);  // scanned as a laser frame before (another --shutter)
      continue;
    }
    const std::string context = " (frame " + std::to_string(frame.index) + ", " + frame.where + ")";
    // The outputs change from here on: a cloud.ply, or this frame's centres, of an
    // earlier scan would pass for this scan's, which may stop on a bad frame.
    if (summary.laser_frames == 0) fs::remove(run_dir / "cloud.ply", ec);
    fs::remove(run_dir / ScanCentersName(frame.index), ec);
    // Its bit depth may come from its file's sBIT; its tags are said once a scan.
    const AnyImage image = ReadFrameImage(&frame, camera, summary.plane_source.string(), &file_warnings, warn_transfer_tags);
    const int width = camera.width(), height = camera.height();
    const double type_full_scale = ImageTypeFullScale(image);
    const SearchAxis axis = options.axis ? *options.axis : frame.gt_axis ? *frame.gt_axis : planes_axis;
    ExtractionOptions given = options.extraction;
    given.method = method;
    given.axis = axis;
    const FrameExtraction fx = RunFrameExtraction(given, frame, image, rig, matched);
    const ExtractionOptions& eo = fx.options;
    if (fx.matched_weights) {
      summary.channel_weights = matched.weights;
      summary.channel_weights_source = matched.Describe();
    }
    if (fx.mosaic_mean && !warned_colour_default) {
      warn(matched.missing + ": colour frames are extracted on the mean of R, G and B, not on the channels that "
           "see the laser (--channel or --weights choose them)");
      warned_colour_default = true;
    }
    std::vector<StripePoint> points;
    int edge_lines_without_points = 0;  // the frame's, for plane identification
    ScanFrameSummary fs_summary;
    fs_summary.index = frame.index;
    try {
      StripeExtractor& extractor = extractors.Get(eo);
      points = extractor.Extract(image);
      edge_lines_without_points = extractor.resolved_options().EdgeLinesWithoutPoints();
      if (eo.method == ExtractionMethod::kSteger) fs_summary.steger_width_px = extractor.resolved_options().expected_width;
      if (const NoiseThreshold* t = extractor.last_noise_threshold()) fs_summary.noise_threshold = *t;
      summary.width_rejected += extractor.last_rejections();
      // A saturated pixel reads its level give or take the read noise: within 1%.
      const double saturated = 0.99 * frame.SaturationLevel(type_full_scale);
      for (const StripePoint& p : points) summary.saturated_points += OnSaturatedPixels(image, p, saturated);
    } catch (const InputError& e) {
      throw InputError(e.where().empty() ? frame.image.string() : e.where(), e.message() + context);
    }
    const bool guessed = !frame.shutter_known || options.shutter != ShutterPattern::kRecorded;
    if (guessed && MostlyAbove(image, eo.threshold)) flooded.push_back(frame.index);
    if (!warned_above_depth && frame.FullScale(type_full_scale) < type_full_scale) {
      const double brightest = Brightest(image);
      if (brightest > frame.FullScale(type_full_scale)) {
        // Raw DN of a deeper ADC stored shifted to the top bits (MSB-aligned), or a wrong bit_depth.
        warn(frame.image.string() + ": a sample reads " + FormatNumber(brightest) + ", above " +
             FormatNumber(frame.FullScale(type_full_scale)) + ", the largest " + std::to_string(frame.bit_depth) +
             "-bit value: the frames are not raw " + std::to_string(frame.bit_depth) +
             "-bit DN (LSB-aligned, docs/run-folder.md); the default threshold and the saturation level assume "
             "they are (check bit_depth, or give --threshold)");
        warned_above_depth = true;
      }
    }
    if (points.empty() && !warned_unknown_depth && type_full_scale == 65535.0 && frame.bit_depth <= 0 &&
        options.extraction.DefaultThreshold()) {
      // A 10- or 12-bit camera's raw DN in 16-bit files lie far below 10% of 65535.
      const double brightest = Brightest(image);
      const int bits = UnscaledBitDepth(brightest);
      warn(frame.image.string() + ": no stripe point in a 16-bit image of unknown bit depth (no bit_depth in the "
           "manifest, no image_sensor.bit_depth in a rig.json, no --bit-depth): the threshold is 10% of 65535" +
           (bits > 0 ? ", and its brightest sample, " + FormatNumber(brightest) + ", fits in " + std::to_string(bits) +
                           " bits" : std::string()) +
           "; a 10- or 12-bit camera's frames need --bit-depth with its ADC's bits (or bit_depth in the manifest), "
           "or --threshold in DN");
      warned_unknown_depth = true;
    }

    if (planes.size() == 1) {
      for (auto& p : points) p.plane = 0;  // one sheet: every stripe point is on it
    } else {
      PlaneIdOptions id_options = options.plane_id;
      id_options.axis = axis;
      id_options.edge_margin = std::max(id_options.edge_margin, edge_lines_without_points + 2);
      const PixelRect region = eo.roi ? *eo.roi : PixelRect{0, 0, width, height};
      const SheetsOfRanks& sheets = sheets_of_ranks.try_emplace(int(axis), triangulator, axis, depth_range).first->second;
      // The working range decides the sheets of lines showing fewer stripes
      // than sheets, where the sheets keep one order (facing projectors'
      // crossing sheets show two in one stripe, which numbering by position
      // counts once: measured to put a stripe on the wrong sheet).
      const bool ranges_lines = depth_range && !sheets.depth_dependent();
      const RankFit range_fit = ranges_lines ? RankFit([&sheets](const std::vector<StripePoint>& line) {
        return sheets.RanksFit(line);
      })
                                             : RankFit();
      PlaneIdentification id = IdentifyPlanes(points, region, int(planes.size()), id_options, range_fit);
      points = std::move(id.points);
      const int uncertain = sheets.Apply(&points);
      if (uncertain > 0 && !warned_uncertain_sheet) {
        const std::string range = depth_range ? " within the working range" : "";
        warn(frame.image.string() + ": " + std::to_string(uncertain) + " stripe point(s) left without a plane: " +
             (sheets.depth_dependent()
                  ? "the sheets of the rig's projectors change places across the image with depth, and these points' "
                    "ranks fit several sheets (or none) at the depths" + range + " their rays meet them"
                  : "on the sheets their ranks give they lie outside the working range") +
             " (docs/extraction.md)");
        warned_uncertain_sheet = true;
      }
      fs_summary.by_edge_chains = id.ok && id.method == PlaneIdMethod::kEdgeChains;
      fs_summary.unidentified_segments = id.unidentified_segments;
      summary.frames_by_edge_chains += fs_summary.by_edge_chains;
      summary.unidentified_segments += id.unidentified_segments;
      if (!id.ok) {
        fs_summary.identified = false;
        fs_summary.identification_error = id.error;
        const bool range_decides = !depth_range && !sheets.depth_dependent() && id.lines_of_fewer_stripes > 0;
        warn(frame.image.string() + ": plane identification failed, its points are not triangulated: " + id.error +
             (range_decides ? "; a working depth range (--depth-range, or the calibration file's depth_min_mm and "
                              "depth_max_mm) would decide which"
                            : ""));
      }
    }
    std::vector<ScanPoint> scan = TriangulatePoints(triangulator, points, frame.world_from_cam, &fs_summary.stats);
    fs::create_directories(run_dir / "centers", ec);
    if (!fs::is_directory(run_dir / "centers")) {
      throw InputError((run_dir / "centers").string(), "cannot create the folder" + (ec ? ": " + ec.message() : ""));
    }
    WriteScanCsv(run_dir / ScanCentersName(frame.index), scan);

    all_posed &= frame.world_from_cam.has_value();
    any_posed |= frame.world_from_cam.has_value();
    // Labels: the ground-truth instance id at each point's pixel.
    Image<float> instance;
    if (frame.gt_buffers) {
      try {
        instance = ReadImageChannels(*frame.gt_buffers, {"instance"});
      } catch (const InputError& e) {
        throw InputError(e.where(), e.message() + context);
      }
      if (instance.width != width || instance.height != height) {
        throw InputError(frame.gt_buffers->string(), "the ground truth is " + SizeText(instance.width, instance.height) +
                                                 " but the image is " + SizeText(width, height) + context);
      }
    } else {
      all_labelled = false;
    }
    for (const ScanPoint& s : scan) {
      if (!s.p_in_cam) continue;
      int label = -1;
      if (!instance.empty()) {
        const int x = std::clamp(int(std::lround(s.pixel.u)), 0, width - 1);
        const int y = std::clamp(int(std::lround(s.pixel.v)), 0, height - 1);
        label = int(instance.At(x, y));
      }
      pending.push_back({*s.p_in_cam, s.p_in_world.value_or(Eigen::Vector3d::Zero()), s.p_in_world.has_value(),
                         frame.index, s.pixel.plane, label});
    }
    const TriangulationStats& st = fs_summary.stats;
    summary.stats.points += st.points;
    summary.stats.triangulated += st.triangulated;
    summary.stats.no_plane += st.no_plane;
    summary.stats.no_ray += st.no_ray;
    summary.stats.grazing += st.grazing;
    summary.stats.behind += st.behind;
    summary.frames.push_back(fs_summary);
    ++summary.laser_frames;
  }
  file_warnings.SayRepeats();
  if (!flooded.empty()) warn(FloodLitWarning(flooded, options.shutter, listed.from_listing));
  if (summary.laser_frames == 0) {
    throw InputError(listed.source.string(),
                     "no laser frame to scan" + std::string(summary.other_frames > 0 ? " (only frames without laser light)"
                                                                                      : " in the selected range"));
  }
  const PointCloud cloud = AssembleCloud(pending, frames, camera, rig, options.colour, all_posed, all_labelled,
                                         any_posed, &summary, warn);
  WritePly(run_dir / "cloud.ply", cloud);
  summary.world_frame = all_posed;
  summary.points = summary.stats.points;
  summary.triangulated = int(cloud.points.size());
  return summary;
}

}  // namespace lt

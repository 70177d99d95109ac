// The stripe extraction options of a run's laser frames (--method, --threshold,
// --background, ..., --bayer, --roi) and plane identification's
// (--link-distance, --edge-margin, --min-segment-points), declared once for
// `scan` and `calibrate laser` with the same meaning and defaults
// (docs/pipeline.md, "Frames and extraction"; pipeline/frame_extraction.h
// applies the run-aware defaults to each frame).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/demosaic.h"
#include "pipeline/extraction_options.h"
#include "pipeline/plane_identification.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {

// What the options give, parsed.
struct ParsedExtraction {
  // threshold and background kAuto (NaN) unless given: 10% of each frame's
  // full scale, the image sensor's black level (RunFrameExtraction);
  // threshold_mode kNoise with --threshold auto.
  ExtractionOptions extraction;
  // --transfer was given (even linear): no warning about a file's transfer tag.
  bool transfer_given = false;
  // --method absent: com, or multicom for several laser planes.
  bool method_from_planes = true;
  std::optional<ColorFilter> color_filter;  // --bayer; unset: rig.json's color_filter
  PlaneIdOptions plane_id;
};

struct ExtractionArgs {
  std::string method;      // empty: com, or multicom for several laser planes
  std::string roi;
  std::string weights;
  std::string background;  // empty: the black level
  std::string bayer;       // empty: the rig's color_filter
  std::string transfer = "linear";
  std::string threshold;   // empty: 10% of full scale; a number, or "auto"
  ExtractionOptions options;  // the numeric options, bound directly
  PlaneIdOptions plane_id;
  std::vector<CLI::Option*> declared;

  ExtractionArgs() { options.background = ExtractionOptions::kAuto; }

  void Declare(CLI::App* cmd) {
    auto add = [&](CLI::Option* o) { declared.push_back(o); return o; };
    auto& e = options;
    add(cmd->add_option("--method", method,
                        "max | com | multicom | steger (default: com, multicom for several laser planes)"));
    add(cmd->add_option("--roi", roi, "Search only in X,Y,W,H (pixels)"));
    add(cmd->add_option("--threshold", threshold,
                        "Minimum stripe peak in image DN (default: 10% of the frame's full scale, 2^bit_depth - 1, "
                        "times the sum of the positive channel weights), or 'auto': each frame's background + 6 x its "
                        "noise (docs/extraction.md)"))
        ->check(ThresholdValue());
    add(cmd->add_option("--high-threshold", e.high_threshold,
                        "steger: high hysteresis threshold, which each chain must reach somewhere (default: the "
                        "threshold)"))
        ->check(FiniteNumber());
    add(cmd->add_option("--background", background,
                        "Level subtracted before centroid and width (default: black level), or 'local': per peak, a "
                        "line through the levels just outside its window (ambient light; max, com, multicom)"));
    add(cmd->add_option("--window", e.window, "com: half window in pixels (0: from the peak width)"))
        ->capture_default_str();
    add(cmd->add_option("--min-width", e.min_width,
                        "Peaks narrower (FWHM, pixels) must continue on the adjacent search lines to count (hot "
                        "pixels do not); 0: no check"))
        ->capture_default_str();
    add(cmd->add_option("--max-width", e.max_width, "Maximum peak FWHM in pixels (0: none)"))->capture_default_str();
    add(cmd->add_option("--width", e.expected_width,
                        "steger: expected stripe FWHM in pixels (default: measured on each frame, from the FWHM of "
                        "each search line's brightest peak, docs/extraction.md)"))
        ->check(FiniteNumber());
    add(cmd->add_option("--sigma", e.sigma, "steger: filter sigma in pixels (0: from --width)"))->capture_default_str();
    add(cmd->add_option("--max-angle-deg", e.max_angle_deg, "steger: largest stripe angle from the search normal"))
        ->capture_default_str();
    add(cmd->add_option("--channel", e.channel,
                        "Colour images: channel holding the laser (0-based; default: the R, G, B weights matched to "
                        "the rig's laser wavelengths and quantum efficiency)"));
    add(cmd->add_option("--weights", weights, "Colour images: channel weights, e.g. 1,0,0"));
    add(cmd->add_option("--bayer", bayer,
                        "The raw frames' mosaic: rggb | bggr | grbg | gbrg | none (default: rig.json's color_filter; "
                        "none without a rig)"));
    add(cmd->add_option("--transfer", transfer,
                        "How the image values encode light: linear | srgb | gamma=G (8- and 16-bit images; srgb: webcams, "
                        "phones, most JPEGs; linearized before extraction, --threshold and --background in linear units)"))
        ->capture_default_str();
    add(cmd->add_option("--threads", e.threads, "Worker threads (0: all)"))->capture_default_str();
    add(cmd->add_option("--link-distance", plane_id.link_distance,
                        "Plane identification: max step across between lines (px)"))
        ->capture_default_str();
    add(cmd->add_option("--edge-margin", plane_id.edge_margin, "Plane identification: edge connectivity distance (px)"))
        ->capture_default_str();
    add(cmd->add_option("--min-segment-points", plane_id.min_segment_points,
                        "Plane identification: smaller segments are noise"))
        ->capture_default_str();
  }

  // Throws lt::InputError naming the option for a bad value.
  ParsedExtraction Parse() const {
    ParsedExtraction p;
    ExtractionOptions& e = p.extraction;
    e = options;
    p.method_from_planes = method.empty();
    e.method = ParseMethod(method.empty() ? "com" : method, "--method");
    if (!threshold.empty()) ParseThreshold(threshold, "--threshold", &e.threshold, &e.threshold_mode);
    if (!background.empty()) ParseBackground(background, "--background", &e.background, &e.background_mode);
    if (!roi.empty()) e.roi = ParseRoi(roi, "--roi");
    ParseTransfer(transfer, "--transfer", &e.transfer, &e.gamma);
    for (const CLI::Option* o : declared) p.transfer_given |= o->get_name() == "--transfer" && o->count() > 0;
    if (!weights.empty()) e.channel_weights = ParseNumberList(weights, "--weights");
    if (!bayer.empty()) p.color_filter = ParseBayerPattern(bayer, "--bayer");
    p.plane_id = plane_id;
    return p;
  }

  // The options given on the command line ("--threshold, --bayer"), "" for
  // none; `except`: one to leave out.
  std::string Given(const std::string& except = "") const {
    std::string names;
    for (const CLI::Option* o : declared) {
      if (o->count() > 0 && o->get_name() != except) names += (names.empty() ? "" : ", ") + o->get_name();
    }
    return names;
  }
};

}  // namespace lt::cli

// `lasertwin extract IMAGE... --method max|com|multicom|steger [--roi X,Y,W,H]
// [--axis rows|cols] [--out FILE.csv | DIR] [--planes N] ...`: laser stripe
// centres of camera images as CSV (u,v,width,strength[,plane]).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <type_traits>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include "core/error.h"
#include "core/image_io.h"
#include "pipeline/demosaic.h"
#include "pipeline/extract_transfer.h"
#include "pipeline/image_file_facts.h"
#include "pipeline/plane_identification.h"
#include "pipeline/stripe_csv.h"
#include "pipeline/stripe_extractor.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {
namespace {

struct ExtractArgs {
  std::vector<std::string> images;
  std::string method;  // empty: com, or multicom with --planes above 1
  std::string axis = "rows";
  std::string roi;
  std::string weights;
  std::string bayer = "none";
  std::string out;
  std::string background = "0";
  std::string threshold;  // empty: 10% of full scale; a number, or "auto"
  std::string transfer = "linear";
  bool transfer_given = false;  // --transfer on the command line (even linear): no warning about a file's tag
  ExtractionOptions options;
  int planes = 0;
  PlaneIdOptions plane_options;
};

// A threshold for notes: as given, or a measured one (--threshold auto) in 4
// significant digits, as its "threshold auto" note prints it.
std::string ThresholdText(double threshold, const ExtractionOptions& o) {
  if (o.threshold_mode != ThresholdMode::kNoise) return FormatNumber(threshold);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", threshold);
  return buf;
}

// Why a mono image gave no point when its brightest pixel (in the ROI) is below
// the threshold: that value, the threshold, and for 16-bit images the bits its
// values fit in (a 12-bit camera's frames stored unscaled in 16-bit files read
// far below the default, 10% of 65535). Empty when the image reaches the
// threshold or is not mono (its channels are weighted first).
template <typename T>
std::string DimImageNote(const Image<T>& im, const StripeExtractor& extractor, const ExtractionOptions& o) {
  if (im.channels != 1 || o.bayer != ColorFilter::kMono) return "";
  const PixelRect r = o.roi ? *o.roi : PixelRect{0, 0, im.width, im.height};
  if (r.x < 0 || r.y < 0 || r.x + r.width > im.width || r.y + r.height > im.height) return "";
  double brightest = -std::numeric_limits<double>::infinity();
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x) brightest = std::max(brightest, double(im.At(x, y)));
  const bool linearized = o.transfer != Transfer::kLinear && std::is_integral_v<T>;
  if (linearized) {  // the threshold is in linear units (--transfer)
    const double full = double(std::numeric_limits<T>::max());
    brightest = std::round(10 * full * DecodeTransfer(o.transfer, o.gamma, brightest / full)) / 10;
  }
  const double threshold = extractor.ThresholdFor<T>();
  if (!(brightest < threshold)) return "";
  std::string note = "its brightest pixel" + std::string(o.roi ? " in the ROI" : "") + " is " + FormatNumber(brightest) +
                     (linearized ? " linearized" : "") + ", below the threshold " + ThresholdText(threshold, o);
  if (std::is_same_v<T, uint16_t> && o.DefaultThreshold()) {
    note += " (10% of 65535)";
    if (const int bits = UnscaledBitDepth(brightest)) {
      const double full = std::ldexp(1.0, bits) - 1;
      note += "; its values fit in " + std::to_string(bits) + " bits: for a " + std::to_string(bits) +
              "-bit camera's frames stored unscaled give --threshold, e.g. " + FormatNumber(std::round(full) / 10) +
              " for 10% of " + FormatNumber(full);
    }
  }
  return note;
}

void Run(ExtractArgs& a) {
  ExtractionOptions& o = a.options;
  o.method = ParseMethod(a.method.empty() ? (a.planes > 1 ? "multicom" : "com") : a.method, "--method");
  o.axis = ParseAxis(a.axis, "--axis");
  if (!a.roi.empty()) o.roi = ParseRoi(a.roi, "--roi");
  if (!a.weights.empty()) o.channel_weights = ParseNumberList(a.weights, "--weights");
  o.bayer = ParseBayerPattern(a.bayer, "--bayer");
  ParseBackground(a.background, "--background", &o.background, &o.background_mode);
  if (!a.threshold.empty()) ParseThreshold(a.threshold, "--threshold", &o.threshold, &o.threshold_mode);
  ParseTransfer(a.transfer, "--transfer", &o.transfer, &o.gamma);
  a.plane_options.axis = o.axis;
  if (a.planes < 0) throw InputError("--planes", "must be >= 1");
  if (a.planes > 0) a.plane_options.Check();
  StripeExtractor extractor(o);  // validates the options
  if (a.planes > 1 && FindsOneStripePerLine(o.method)) {
    std::cerr << "lasertwin: warning: " << MethodName(o.method) << " finds one stripe per search line, but --planes is "
              << a.planes << ": use --method multicom or steger to see every stripe\n";
  }

  namespace fs = std::filesystem;
  const bool several = a.images.size() > 1;
  if (several && a.out.empty()) throw InputError("--out", "several images need --out DIR (one CSV per image)");
  // --out is a folder (one DIR/<image name>.csv per image) for several images,
  // for an existing folder and for a name ending in '/'; else the CSV file of
  // the one image, whose folder must exist.
  std::error_code ec;
  const bool to_folder = !a.out.empty() && (several || fs::is_directory(a.out, ec) || a.out.back() == '/' ||
                                            fs::path(a.out).filename().empty());
  if (to_folder) {
    std::set<std::string> stems;
    for (const auto& image : a.images) {
      if (!stems.insert(fs::path(image).stem().string()).second) {
        throw InputError(image, "another image has the same name; their CSV files would collide in " + a.out);
      }
    }
    fs::create_directories(a.out, ec);
    if (!fs::is_directory(a.out, ec)) {
      throw InputError("--out", "cannot create the output folder " + a.out +
                                    (fs::exists(a.out, ec) ? " (a file of that name exists)" : ""));
    }
  } else if (!a.out.empty()) {
    RequireOutputFolder("--out", a.out);
  }
  size_t total = 0;
  WidthRejections rejected;
  // Extractors for images whose declared bits are stored unscaled (a 16-bit
  // PNG with sBIT 12 and no sample above 4095), by that full scale: the
  // default threshold is 10% of it, not of the sample type's.
  std::map<double, std::unique_ptr<StripeExtractor>> unscaled_extractors;
  bool unscaled_noted = false, float_scale_noted = false;
  // Each file warning once, on the first image it concerns (a batch of a
  // phone's JPEGs would repeat it for every one); the others are counted at the end.
  ImageFileWarner file_warnings([](const std::string& w) { std::cerr << "lasertwin: warning: " << w << "\n"; }, "image");
  // The first image's size: the frames of one camera share it, so an image of
  // another size (another camera's, a cropped or resized copy) is named.
  std::string first_image;
  int first_width = 0, first_height = 0;
  // The CSV file of an image (with --out).
  auto target_of = [&](const std::string& image) {
    return to_folder ? fs::path(a.out) / (fs::path(image).stem().string() + ".csv") : fs::path(a.out);
  };
  // One image's points, identified and written (or printed).
  auto extract_one = [&](const std::string& image) {
    ImageFileFacts facts;
    AnyImage img = ReadImage(image, AlphaChannel::kDrop, &facts);
    file_warnings.Check(image, facts, a.transfer_given);
    std::vector<StripePoint> points;
    StripeExtractor* ex = &extractor;
    int width = 0, height = 0;
    try {
      std::visit([&](const auto& im) { width = im.width, height = im.height; }, img);
      if (first_image.empty()) {
        first_image = image, first_width = width, first_height = height;
      } else if (width != first_width || height != first_height) {
        std::cerr << "lasertwin: warning: " << image << " is " << width << "x" << height << ", the first image ("
                  << first_image << ") " << first_width << "x" << first_height
                  << ": extracted on its own (frames of one camera have one size)\n";
      }
      // A file declaring bits stored unscaled (sBIT) has its own default threshold.
      if (facts.unscaled_full_scale > 0) {
        const ExtractionOptions declared = OptionsForImageFile(o, facts);  // refuses --transfer
        if (o.DefaultThreshold()) {
          std::unique_ptr<StripeExtractor>& slot = unscaled_extractors[declared.threshold];
          if (!slot) slot = std::make_unique<StripeExtractor>(declared);
          ex = slot.get();
          if (!unscaled_noted) std::cerr << "lasertwin: note: " << image << ": " << UnscaledBitsNote(facts) << "\n";
          unscaled_noted = true;
        }
      }
      points = ex->Extract(img);
      rejected += ex->last_rejections();
    } catch (const InputError& e) {
      throw InputError(image, e.message());
    }
    total += points.size();
    if (const NoiseThreshold* t = ex->last_noise_threshold()) {
      std::cerr << "lasertwin: note: " << image << ": threshold auto: " << DescribeNoiseThreshold(*t) << "\n";
    }
    if (const auto* f = std::get_if<Image<float>>(&img); f && o.DefaultThreshold() && !float_scale_noted) {
      float largest = 0;
      for (float v : f->pixels) largest = std::max(largest, v);
      const std::string note = FloatScaleNote(largest);
      if (!note.empty()) std::cerr << "lasertwin: note: " << image << ": " << note << "\n";
      float_scale_noted = !note.empty();
    }
    if (points.empty()) {
      const std::string why = std::visit([&](const auto& im) { return DimImageNote(im, *ex, ex->options()); }, img);
      if (!why.empty()) std::cerr << "lasertwin: note: " << image << ": " << why << "\n";
    }
    if (a.planes > 0) {
      PixelRect region = o.roi ? *o.roi : PixelRect{0, 0, width, height};
      // Edge connectivity must reach past the lines a method cannot measure.
      PlaneIdOptions id_options = a.plane_options;
      id_options.edge_margin =
          std::max(id_options.edge_margin, ex->resolved_options().EdgeLinesWithoutPoints() + 2);
      PlaneIdentification id = IdentifyPlanes(points, region, a.planes, id_options);
      if (!id.ok) std::cerr << "lasertwin: warning: " << image << ": plane identification failed: " << id.error << "\n";
      if (id.ok && id.method == PlaneIdMethod::kEdgeChains) {
        std::cerr << "lasertwin: note: " << image << ": planes numbered by the edge chains (the stripes' order could not: "
                  << id.order_error << ")\n";
      }
      if (id.unidentified_segments > 0) {
        std::cerr << "lasertwin: note: " << image << ": " << id.unidentified_segments
                  << " stripe segment(s) left without a plane (their place among the stripes is not certain)\n";
      }
      points = std::move(id.points);
    }
    if (a.out.empty()) {
      std::cout << FormatStripeCsv(points, a.planes > 0);
    } else {
      WriteStripeCsv(target_of(image), points, a.planes > 0);
    }
  };
  // A batch goes on past an image it cannot read or measure (each is named on
  // stderr, and gets no CSV), then fails as a whole, so one bad file among
  // thousands costs only its own result. An image that fails leaves no CSV of
  // an earlier run under its name (it would pass for this run's).
  std::vector<std::string> failed;
  for (const auto& image : a.images) {
    try {
      extract_one(image);
    } catch (const InputError& e) {
      if (!a.out.empty()) fs::remove(target_of(image), ec);
      if (!several) throw;
      std::cerr << "lasertwin: error: " << e.what() << "\n";
      failed.push_back(image);
    }
  }
  file_warnings.SayRepeats();
  for (const std::string& note : WidthRejectionNotes(rejected, o)) std::cerr << "lasertwin: note: " << note << "\n";
  if (total == 0 && failed.size() < a.images.size()) std::cerr << "lasertwin: note: " << NoStripePointsNote(o) << "\n";
  if (!failed.empty()) {
    throw InputError("", std::to_string(failed.size()) + " of " + std::to_string(a.images.size()) +
                             " images failed (named above; the others' CSV files are in " + a.out + "), first " +
                             failed.front());
  }
}

void AddExtract(CLI::App& app) {
  auto args = std::make_shared<ExtractArgs>();
  auto* cmd = app.add_subcommand("extract", "Find laser stripe centres in images (CSV: u,v,width,strength[,plane])");
  cmd->add_option("images", args->images, "Image files (PNG, TIFF, EXR, JPEG, PGM; 8/16-bit or float; an alpha channel is left out)")->required();
  cmd->add_option("--method", args->method,
                  "max | com | multicom | steger (default: com, multicom with --planes above 1)");
  cmd->add_option("--axis", args->axis, "rows (stripes run top to bottom) | cols (left to right)")
      ->capture_default_str();
  cmd->add_option("--roi", args->roi, "Search only in X,Y,W,H (pixels)");
  cmd->add_option("--out", args->out, "CSV file (one image; its folder must exist) or folder (several images, or an existing folder: "
                  "FOLDER/<image name>.csv); default: standard output");
  auto& o = args->options;
  cmd->add_option("--threshold", args->threshold,
                  "Minimum stripe peak intensity in image units (default: 10% of full scale, times the sum of the "
                  "positive --weights), or 'auto': each image's background + 6 x its noise (docs/extraction.md)")
      ->check(ThresholdValue());
  cmd->add_option("--high-threshold", o.high_threshold, "steger: high hysteresis threshold, which each chain must reach somewhere (default: the threshold)")
      ->check(FiniteNumber());
  cmd->add_option("--background", args->background,
                  "Level subtracted before centroid and width, or 'local': per peak, a line through the levels just "
                  "outside its window (ambient light; max, com, multicom)")
      ->capture_default_str();
  cmd->add_option("--window", o.window, "com: half window in pixels (0: from the peak width)")->capture_default_str();
  cmd->add_option("--min-width", o.min_width, "Peaks narrower (FWHM, pixels) must continue on the adjacent search lines to count (hot pixels do not); 0: no check")->capture_default_str();
  cmd->add_option("--max-width", o.max_width, "Maximum peak FWHM in pixels (0: none)")->capture_default_str();
  cmd->add_option("--width", o.expected_width,
                  "steger: expected stripe FWHM in pixels (default: measured on each image, from the FWHM of "
                  "each search line's brightest peak, docs/extraction.md)")
      ->check(FiniteNumber());
  cmd->add_option("--sigma", o.sigma, "steger: filter sigma in pixels (0: from --width)")->capture_default_str();
  cmd->add_option("--max-angle-deg", o.max_angle_deg, "steger: largest stripe angle from the search normal")
      ->capture_default_str();
  cmd->add_option("--channel", o.channel, "Colour images: channel holding the laser (0-based)");
  cmd->add_option("--weights", args->weights, "Colour images: channel weights, e.g. 1,0,0");
  cmd->add_option("--bayer", args->bayer,
                  "Raw Bayer mosaic: rggb | bggr | grbg | gbrg (demosaiced, then extracted on the mean of R, G, B "
                  "or on --channel/--weights of them) | none")
      ->capture_default_str();
  CLI::Option* transfer = cmd->add_option("--transfer", args->transfer,
                  "How the image values encode light: linear | srgb | gamma=G (8- and 16-bit images; srgb: webcams, "
                  "phones, most JPEGs; linearized before extraction, --threshold and --background in linear units)")
      ->capture_default_str();
  cmd->add_option("--threads", o.threads, "Worker threads (0: all)")->capture_default_str();
  cmd->add_option("--planes", args->planes, "Identify N laser planes (adds the plane column)");
  cmd->add_option("--link-distance", args->plane_options.link_distance,
                  "Plane identification: max step across between adjacent lines (pixels)")
      ->capture_default_str();
  cmd->add_option("--edge-margin", args->plane_options.edge_margin,
                  "Plane identification: edge connectivity distance (pixels; at least steger's edge margin + 2)")
      ->capture_default_str();
  cmd->add_option("--min-segment-points", args->plane_options.min_segment_points,
                  "Plane identification: smaller segments are noise")
      ->capture_default_str();
  cmd->callback([args, transfer] {
    args->transfer_given = transfer->count() > 0;
    Run(*args);
  });
}

}  // namespace

LT_REGISTER_COMMAND("extract", AddExtract);

}  // namespace lt::cli

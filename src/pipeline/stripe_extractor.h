// Laser stripe extraction: finds the subpixel centres of laser stripes in an
// image (docs/extraction.md). An extractor keeps its working buffers and its
// thread arena between calls, so extracting frame after frame allocates
// nothing once the buffers have grown to the frame size.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "pipeline/auto_threshold.h"
#include "pipeline/extraction_options.h"
#include "pipeline/stripe_point.h"

namespace lt {

class StripeExtractor {
 public:
  // Validates the options (Check()).
  explicit StripeExtractor(ExtractionOptions options);
  ~StripeExtractor();
  StripeExtractor(const StripeExtractor&) = delete;
  StripeExtractor& operator=(const StripeExtractor&) = delete;

  const ExtractionOptions& options() const;
  // The options as the last Extract used them: steger's automatic width
  // (expected_width kAuto) resolved to the one measured on that frame
  // (kDefaultExpectedWidth before any frame), and with threshold_mode kNoise
  // `threshold` that frame's (NaN before any frame). Its
  // EdgeLinesWithoutPoints() are that frame's.
  const ExtractionOptions& resolved_options() const;

  // Finds stripe points, ordered by search line (row or column) and then
  // across it. An 8- or 16-bit image with options().transfer not linear is
  // linearized first (pipeline/extract_transfer.h); a float one is refused.
  // Bad input (empty image, ROI outside the image, channel count that does
  // not fit the options) throws lt::InputError with an empty `where` (the
  // caller knows the file name). `points` is cleared first; its capacity is
  // reused.
  template <typename T>
  void Extract(const ImageView<T>& image, std::vector<StripePoint>* points);
  template <typename T>
  std::vector<StripePoint> Extract(const ImageView<T>& image) {
    std::vector<StripePoint> points;
    Extract(image, &points);
    return points;
  }
  std::vector<StripePoint> Extract(const AnyImage& image);

  // Candidate peaks the last Extract dropped for their width (max, com,
  // multicom; zero for steger), so callers can tell the user.
  const WidthRejections& last_rejections() const;

  // threshold_mode kNoise: how the last Extract set its threshold (per frame,
  // per ROI; pipeline/auto_threshold.h); nullptr before any frame and with
  // kFixed.
  const NoiseThreshold* last_noise_threshold() const;

  // The threshold used for images of sample type T (resolves kAuto; with
  // threshold_mode kNoise the last frame's, NaN before any).
  template <typename T>
  double ThresholdFor() const;

 private:
  // Extract on an image in linear units, with the threshold resolved.
  template <typename T>
  void ExtractLinear(const ImageView<T>& image, double threshold, std::vector<StripePoint>* points);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Notes for the user (one line each, without "note: "; none when nothing was
// rejected) naming the counts of `rejected` and the option to change, e.g. "312
// candidate peaks were narrower than --min-width 1.5 px without continuing on
// the adjacent search lines and rejected (hot pixels or noise spikes; lower
// --min-width to keep them)".
std::vector<std::string> WidthRejectionNotes(const WidthRejections& rejected, const ExtractionOptions& options);
// The note when no stripe point was found at all: what to check (for steger,
// also --width).
std::string NoStripePointsNote(const ExtractionOptions& options);

}  // namespace lt

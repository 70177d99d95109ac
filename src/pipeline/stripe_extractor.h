// Laser stripe extraction: finds the subpixel centres of laser stripes in an
// image (docs/extraction.md). An extractor keeps its working buffers and its
// thread arena between calls, so extracting frame after frame allocates
// nothing once the buffers have grown to the frame size.
#pragma once

#include <memory>
#include <vector>

#include "core/image.h"
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

  // Finds stripe points, ordered by search line (row or column) and then
  // across it. Bad input (empty image, ROI outside the image, channel count
  // that does not fit the options) throws lt::InputError with an empty `where`
  // (the caller knows the file name). `points` is cleared first; its capacity is
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

  // The threshold used for images of sample type T (resolves kAuto).
  template <typename T>
  double ThresholdFor() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lt

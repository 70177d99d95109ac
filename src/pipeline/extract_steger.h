// Steger's curvilinear-structure detector for bright laser stripes (internal to
// the extractor; see docs/extraction.md). Holds its kernels and buffers so
// repeated frames allocate nothing.
#pragma once

#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "pipeline/extract_methods.h"
#include "pipeline/gaussian_filter.h"

namespace lt {

class StegerDetector {
 public:
  // `options.expected_width` must be a width, not kAuto.
  explicit StegerDetector(const ExtractionOptions& options);
  // Sets the detector up for other options (kernels, threshold conversion,
  // margins), keeping its buffers.
  void Configure(const ExtractionOptions& options);

  // Must be called inside the extractor's task arena.
  template <typename T>
  void Run(const ImageView<T>& image, const MethodParams& params, std::vector<StripePoint>* out);

  // Contrast (peak intensity of a stripe of the expected width) per unit of
  // second derivative: thresholds and strengths convert with it.
  double contrast_per_curvature() const { return contrast_per_curvature_; }

 private:
  struct Candidate {
    int x, y;
    float px, py;  // subpixel line point
    float nx, ny;  // unit normal (across the stripe)
    float response;  // -(second derivative along the normal)
  };
  struct Scratch {
    std::vector<uint8_t> colmark;
    std::vector<int> intervals;  // pairs [begin, end)
    std::vector<float> line, h0, h1, h2, rx, ry, rxx, rxy, ryy;
  };

  template <typename T>
  void DetectBand(const ImageView<T>& image, int y0, int y1, double candidate_level, double low_curv,
                  std::vector<Candidate>* out);
  void LinkAndSelect(double high_curv);
  template <typename T>
  bool Refine(const ImageView<T>& image, const Candidate& c, StripePoint* point) const;

  ExtractionOptions options_;
  GaussianKernels kernels_;
  double contrast_per_curvature_ = 1;
  double min_abs_nx_ = 0;
  int row_margin_ = 0;  // rows this close to the top or bottom give no points
  tbb::enumerable_thread_specific<Scratch> scratch_;
  std::vector<std::vector<Candidate>> band_candidates_;
  std::vector<Candidate> candidates_;
  std::vector<int> parent_, row_start_;
  std::vector<float> component_max_;
  std::vector<int> selected_;
  std::vector<StripePoint> refined_;
  std::vector<uint8_t> refined_ok_;
};

}  // namespace lt

// Steger's automatic expected width (--width unset): measured on a frame
// from the brightest peak of each search line (pipeline/stripe_extractor.cpp
// finds them by the maximum search; docs/extraction.md, "Steger").
#pragma once

#include <vector>

#include "core/image.h"
#include "pipeline/stripe_point.h"

namespace lt {

// `work`: a mono image whose rows are the search lines; `peaks`: the
// brightest peak of each line (in work's coordinates, their FWHM in width),
// whose widths become the widths within valleys (a neighbouring stripe's
// light does not widen them). Returns the expected width:
// the 90th percentile across the stripe, at most twice the median, to 0.1 px;
// ExtractionOptions::kDefaultExpectedWidth when there is no peak.
template <typename T>
double MeasureStegerWidth(const ImageView<T>& work, double background, std::vector<StripePoint>* peaks);

}  // namespace lt

// The notes StripeExtractor's callers print (stripe_extractor.h).
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "pipeline/stripe_extractor.h"

namespace lt {

std::vector<std::string> WidthRejectionNotes(const WidthRejections& rejected, const ExtractionOptions& o) {
  std::vector<std::string> notes;
  if (rejected.narrow > 0) {
    notes.push_back(std::to_string(rejected.narrow) + " candidate peak" + (rejected.narrow == 1 ? " was" : "s were") +
                    " narrower than --min-width " + FormatNumber(o.min_width) +
                    " px without continuing on the adjacent search lines and rejected (hot pixels or noise "
                    "spikes; lower --min-width to keep them)");
  }
  if (rejected.wide > 0) {
    notes.push_back(std::to_string(rejected.wide) + " candidate peak" + (rejected.wide == 1 ? " was" : "s were") +
                    " wider than --max-width " + FormatNumber(o.max_width) +
                    " px and rejected (blobs of ambient light, or a stripe wider than that: raise --max-width)");
  }
  return notes;
}

std::string NoStripePointsNote(const ExtractionOptions& o) {
  std::string note = o.threshold_mode == ThresholdMode::kNoise
                         ? "no stripe points found; check --threshold (auto: each image's background + 6 x its noise, "
                           "in the notes above), --roi and --axis"
                         : "no stripe points found; check --threshold (the default is 10% of the image's full scale), "
                           "--roi and --axis";
  if (o.method == ExtractionMethod::kSteger && !std::isnan(o.expected_width)) {
    note += ", and --width (" + FormatNumber(o.expected_width) + " px): steger finds only stripes of about that width";
  }
  return note;
}

}  // namespace lt

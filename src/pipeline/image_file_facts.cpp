#include "pipeline/image_file_facts.h"

#include <cmath>

#include "core/error.h"

namespace lt {

namespace {

// OpenImageIO's (and the TIFF standard's) meaning of Orientation 2..8.
const char* OrientationText(int orientation) {
  switch (orientation) {
    case 2: return "mirrored left to right";
    case 3: return "turned 180 degrees";
    case 4: return "mirrored top to bottom";
    case 5: return "transposed";
    case 6: return "turned 90 degrees clockwise";
    case 7: return "transversed";
    case 8: return "turned 90 degrees counter-clockwise";
  }
  return "unknown";
}

// "its sBIT chunk declares 12 significant bits, stored unscaled (no sample
// above 4095)": what a file with facts.unscaled_full_scale says.
std::string UnscaledBitsClause(const ImageFileFacts& facts) {
  return "its sBIT chunk declares " + std::to_string(facts.significant_bits) +
         " significant bits, stored unscaled (no sample above " + FormatNumber(facts.unscaled_full_scale) + ")";
}

}  // namespace

ImageFileWarner::ImageFileWarner(std::function<void(const std::string&)> warn, std::string noun)
    : warn_(std::move(warn)), noun_(std::move(noun)) {}

void ImageFileWarner::Say(const std::string& file, const std::string& text) {
  auto& [first, count] = seen_[text];
  if (count++ > 0) return;
  first = file;
  if (warn_) warn_(file + ": " + text);
}

void ImageFileWarner::Check(const std::string& file, const ImageFileFacts& facts, bool transfer_given) {
  for (const std::string& w : ImageFileWarnings(facts, transfer_given)) Say(file, w);
}

void ImageFileWarner::SayRepeats() const {
  if (!warn_) return;
  for (const auto& [text, seen] : seen_) {
    if (seen.second < 2) continue;
    warn_("the same as for " + seen.first + " (" + text.substr(0, text.find(':')) + ") holds for " +
          std::to_string(seen.second - 1) + " more " + noun_ + (seen.second > 2 ? "s" : ""));
  }
}

std::vector<std::string> ImageFileWarnings(const ImageFileFacts& facts, bool transfer_given) {
  std::vector<std::string> out;
  if (!facts.encoding.empty() && !transfer_given) {
    const std::string keep = " (--transfer linear reads them as they are, without this warning)";
    if (facts.gamma > 0) {
      out.push_back("has " + facts.encoding + ": its values encode light as value = light^(1/" +
                    FormatNumber(facts.gamma) + "), but are read as linear: give --transfer gamma=" +
                    FormatNumber(facts.gamma) + " to linearize them" + keep);
    } else if (facts.encoding == "an sRGB chunk") {
      out.push_back("has " + facts.encoding + ": its values encode light by the sRGB curve, but are read as linear: "
                    "give --transfer srgb to linearize them" + keep);
    } else {
      out.push_back("has " + facts.encoding + ": its values likely encode light by a curve (the sRGB one for most "
                    "cameras' and phones' JPEGs), but are read as linear: give --transfer srgb if so" + keep);
    }
  }
  if (facts.orientation >= 2 && facts.orientation <= 8) {
    out.push_back("has an Orientation tag of " + std::to_string(facts.orientation) + " (shown " +
                  OrientationText(facts.orientation) +
                  "): it is not applied: the pixels are read as stored, and u, v are in that grid (an image viewer "
                  "and OpenCV's imread show the image turned or mirrored)");
  }
  return out;
}

std::string UnscaledBitsNote(const ImageFileFacts& facts) {
  if (facts.unscaled_full_scale <= 0) return "";
  return UnscaledBitsClause(facts) + ": the default threshold is 10% of " + FormatNumber(facts.unscaled_full_scale);
}

std::string FloatScaleNote(double largest) {
  if (!(largest > 1)) return "";
  return "a float image whose samples reach " + FormatNumber(largest) +
         ", not 0..1 (counts stored as float, or 32-bit integers): the default threshold, 0.1, assumes 0..1; give "
         "--threshold in its units (e.g. " + FormatNumber(std::round(largest) / 10) + ", 10% of that)";
}

int DeclaredUnscaledBits(const ImageFileFacts& facts) {
  return facts.unscaled_full_scale > 0 ? facts.significant_bits : 0;
}

ExtractionOptions OptionsForImageFile(const ExtractionOptions& o, const ImageFileFacts& facts) {
  if (facts.unscaled_full_scale <= 0) return o;
  if (o.transfer != Transfer::kLinear) {
    throw InputError("", UnscaledBitsClause(facts) +
                             ": --transfer decodes samples on the full 8- or 16-bit scale only; scale the image's "
                             "values to it first");
  }
  ExtractionOptions out = o;
  if (std::isnan(o.threshold)) out.threshold = 0.1 * facts.unscaled_full_scale * o.WeightedFullScale();
  return out;
}

}  // namespace lt

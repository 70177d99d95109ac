// What extraction does with what an image file declares (core/image_io.h's
// ImageFileFacts): the default threshold of declared bits stored unscaled, and
// messages for what it does not apply (docs/extraction.md, "Image files from
// real cameras").
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/image_io.h"
#include "pipeline/extraction_options.h"

namespace lt {

// Warnings (one line each, without "warning: " and the file name) for a file
// read with `--transfer linear`: a tag saying its values encode light by a
// curve (unless transfer_given: the user said linear), and an Orientation tag
// that is not applied. Each starts with what the file has, up to the first
// ':' ("has an sRGB chunk", "has an Orientation tag of 6 (shown turned 90
// degrees clockwise)"), so a caller can name it again. Empty when there is
// nothing to say.
std::vector<std::string> ImageFileWarnings(const ImageFileFacts& facts, bool transfer_given);

// Says each warning about a run's files once, on the first file it concerns (a
// batch of a phone's JPEGs would repeat it for every one), and counts the
// other files it holds for, as extract, scan and calibrate report
// ImageFileWarnings.
class ImageFileWarner {
 public:
  // `warn` gets each line without "warning: " (none when empty); `noun` names
  // the files in the count ("image", "frame").
  ImageFileWarner(std::function<void(const std::string&)> warn, std::string noun);
  // Says "FILE: text" the first time `text` comes in the run; later ones are
  // counted.
  void Say(const std::string& file, const std::string& text);
  // ImageFileWarnings(facts, transfer_given) of `file`, each through Say.
  void Check(const std::string& file, const ImageFileFacts& facts, bool transfer_given);
  // At the end of the run: for each text that came for several files, in text
  // order, "the same as for FIRST (HEAD) holds for N more NOUNs", HEAD being
  // the text up to its first ':' (what the file has, for ImageFileWarnings).
  void SayRepeats() const;

 private:
  std::function<void(const std::string&)> warn_;
  std::string noun_;
  std::map<std::string, std::pair<std::string, size_t>> seen_;  // text -> first file, files
};

// The note for an image whose declared bits are stored unscaled (its default
// threshold follows them), e.g. "its sBIT chunk declares 12 significant bits,
// stored unscaled (no sample above 4095): the default threshold is 10% of
// 4095". Empty when facts.unscaled_full_scale is 0.
std::string UnscaledBitsNote(const ImageFileFacts& facts);

// The note for a float image (float or half TIFF and EXR, 32-bit integers
// read as float) whose largest sample is above 1 while the threshold is the
// default, 0.1, which assumes values in 0..1: integer counts stored as float
// (ImageJ's 32-bit TIFFs) put every pixel above it. Empty when largest <= 1.
std::string FloatScaleNote(double largest);

// The bits a file declares and holds unscaled (facts.significant_bits when
// facts.unscaled_full_scale is set), else 0: scan and calibrate laser take them
// as a frame's bit depth when nothing else gives one.
int DeclaredUnscaledBits(const ImageFileFacts& facts);

// The options for extracting an image read with `facts`: `o`, with the default
// threshold (kAuto) made 10% of facts.unscaled_full_scale (times the weights'
// WeightedFullScale) when the file declares bits stored unscaled: a 16-bit PNG
// of 12-bit DN with an sBIT chunk is extracted as a 12-bit image, not as a dim
// 16-bit one. A given threshold is kept. Such a file with a non-linear
// transfer is an InputError (empty `where`): --transfer decodes the sample
// type's full scale.
ExtractionOptions OptionsForImageFile(const ExtractionOptions& o, const ImageFileFacts& facts);

}  // namespace lt

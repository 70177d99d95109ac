// Reading and writing image files (PNG, TIFF, EXR, ... through OpenImageIO).
// Errors (missing, empty, unreadable, truncated file) are lt::InputError naming the
// file; a file OpenImageIO decodes only in part (a truncated TIFF or JPEG) is one
// too, and so is a file of several frames (a multi-page TIFF or animated GIF
// whose second image has the first's size: one frame per file; a second page of
// another size, a thumbnail, is left out).
// Alpha is read as stored (straight, not multiplied into the colour).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/image.h"

namespace lt {

// Reads any image in its own sample type (see AnyImage). Unsigned 8-bit files give
// Image<uint8_t>, unsigned 9..16-bit give Image<uint16_t>, everything else
// Image<float>: half/float as stored, signed and 32/64-bit integers with their raw
// values (an int16 -5 is -5.0f, a uint32 70000 is 70000.0f; no normalisation).
AnyImage ReadImage(const std::filesystem::path& path);

// What ReadImage does with the channel OpenImageIO marks as alpha (PNG's grey+alpha
// and RGBA, TIFF's extra alpha sample, EXR's "A").
enum class AlphaChannel {
  kKeep,  // read as stored, one channel among the others
  kDrop,  // left out: a grey+alpha file gives one channel, RGBA three. A camera
          // frame's alpha is coverage, not light (a frame saved with an opaque alpha
          // is a mono or RGB frame); an image of alpha alone keeps it.
};
AnyImage ReadImage(const std::filesystem::path& path, AlphaChannel alpha);

// What a file declares about its values beyond their sample type, for the
// pipeline to follow or name (docs/extraction.md, "Image files from real cameras").
struct ImageFileFacts {
  // Significant bits the file declares below its sample type's (a PNG's sBIT
  // chunk: 12 in a 16-bit PNG); 0 when it declares none or all. (A PGM's maxval
  // and a TIFF's BitsPerSample 10 or 12 need nothing: OpenImageIO scales those
  // samples to the full 16-bit range.)
  int significant_bits = 0;
  // 2^significant_bits - 1 when every sample (alpha aside) is at most that and
  // some sample has a bit set below the declared top bits: the declared bits
  // stored unscaled (LSB-aligned, as many cameras' tools write them), so that is
  // the data's full scale; 0 otherwise (the sample type's maximum: the bits are
  // MSB-aligned or scaled, as the PNG standard says; a dim frame of such samples
  // is at most 2^significant_bits - 1 too, but its low bits are all clear).
  double unscaled_full_scale = 0;
  // What in the file says its values encode light by a curve, for messages
  // ("an sRGB chunk", "a gAMA chunk (gamma 2.2)", "an ICC profile", "EXIF
  // ColorSpace sRGB"); empty when nothing does or it says linear. (OpenImageIO
  // names every PNG without a gAMA chunk "sRGB", tagged or not: not used.)
  std::string encoding;
  // The gAMA chunk's exponent G (value = light^(1/G)) when it gave `encoding`.
  double gamma = 0;
  // The TIFF/EXIF Orientation tag: 1 (or absent) the pixels as stored are the
  // picture; 2-8 a viewer mirrors or turns them. ReadImage never does.
  int orientation = 1;
};
AnyImage ReadImage(const std::filesystem::path& path, AlphaChannel alpha, ImageFileFacts* facts);

// An image file's size from its header, without reading the pixels (errors as
// ReadImage's for a missing or unreadable file).
struct ImageFileSize {
  int width = 0, height = 0, channels = 0;
  // The sample type ReadImage gives: "8-bit", "16-bit" or "float" (every other type).
  std::string sample_type = {};
};
ImageFileSize ReadImageFileSize(const std::filesystem::path& path);

// Reads an image as float in its own units (no scaling: an 8-bit 255 is 255.0f).
Image<float> ReadImageFloat(const std::filesystem::path& path);
// The same, and the names of the image's channels in the order of the pixels'
// channels (EXR: e.g. {"Z", "N.X", ...}; OpenImageIO may reorder them from the
// file's order, so look channels up by name).
Image<float> ReadImageFloat(const std::filesystem::path& path, std::vector<std::string>* channel_names);

// Reads the named channels of an image (EXR channel names, e.g. {"instance"}) as
// float, in the order asked for, whatever order the file stores them in. A
// channel the file lacks is an InputError naming it.
Image<float> ReadImageChannels(const std::filesystem::path& path, const std::vector<std::string>& names);

// Writes atomically (temporary name, then rename). The format follows the
// extension; PNG takes uint8/uint16, EXR takes float (stored as half unless
// full_float). channel_names (optional) name EXR channels, e.g. {"R","G","B"}.
// Values are written as given (a fourth channel is straight alpha).
void WriteImage(const std::filesystem::path& path, const Image<uint8_t>& image);
void WriteImage(const std::filesystem::path& path, const Image<uint16_t>& image);
void WriteImage(const std::filesystem::path& path, const Image<float>& image, bool full_float = true,
                const std::vector<std::string>& channel_names = {});

}  // namespace lt

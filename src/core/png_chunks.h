// What a PNG file's header chunks declare that OpenImageIO 2.4 does not pass
// on: the sBIT chunk's significant bits (it reports none), and whether the
// file says how its values encode light (it reports "sRGB" for every PNG
// without a gAMA chunk, tagged or not, so a linear camera frame looks like an
// sRGB one). Read from the chunks before the first IDAT; the pixels are not.
#pragma once

#include <filesystem>

namespace lt {

struct PngChunks {
  bool is_png = false;       // the PNG signature and an IHDR were found
  int bit_depth = 0;         // IHDR's, 1..16
  int significant_bits = 0;  // sBIT's largest colour (grey, R, G, B) entry; 0 without sBIT
  bool srgb = false;         // an sRGB chunk
  double gamma = 0;          // a gAMA chunk's exponent G (value = light^(1/G)); 0 without one
  bool icc = false;          // an iCCP chunk (an ICC profile)
};

// Never throws: a file that is no PNG, or whose chunks are damaged, gives what
// was read up to there (OpenImageIO reports the damage when it decodes).
PngChunks ReadPngChunks(const std::filesystem::path& path);

}  // namespace lt

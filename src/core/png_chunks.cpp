#include "core/png_chunks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

namespace lt {

namespace {

uint32_t BigEndian32(const unsigned char* b) {
  return uint32_t(b[0]) << 24 | uint32_t(b[1]) << 16 | uint32_t(b[2]) << 8 | uint32_t(b[3]);
}

}  // namespace

PngChunks ReadPngChunks(const std::filesystem::path& path) {
  PngChunks out;
  std::ifstream in(path, std::ios::binary);
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  unsigned char sig[8];
  if (!in.read(reinterpret_cast<char*>(sig), 8) || std::memcmp(sig, kSignature, 8) != 0) return out;
  int colour_type = -1;
  for (int k = 0; k < 1000; ++k) {  // the header chunks come before IDAT; 1000 bounds a damaged file
    unsigned char head[8];
    if (!in.read(reinterpret_cast<char*>(head), 8)) return out;
    const uint32_t length = BigEndian32(head);
    const std::string type(reinterpret_cast<const char*>(head) + 4, 4);
    if (type == "IDAT" || type == "IEND" || length > (1u << 31)) return out;
    const bool wanted = type == "IHDR" || type == "sBIT" || type == "gAMA";
    if (!wanted || length > 64) {
      if (type == "sRGB") out.srgb = true;
      if (type == "iCCP") out.icc = true;
      in.seekg(std::streamoff(length) + 4, std::ios::cur);  // data and CRC
      if (!in) return out;
      continue;
    }
    unsigned char data[64 + 4];
    if (!in.read(reinterpret_cast<char*>(data), std::streamsize(length) + 4)) return out;
    if (type == "IHDR" && length == 13) {
      out.is_png = true;
      out.bit_depth = data[8];
      colour_type = data[9];
    } else if (type == "sBIT" && colour_type >= 0 && colour_type != 3) {  // a palette's sBIT is its colours'
      // grey; R G B; grey alpha; R G B alpha: the colour entries, not alpha's.
      const uint32_t colours = (colour_type == 0 || colour_type == 4) ? 1 : 3;
      for (uint32_t i = 0; i < colours && i < length; ++i) out.significant_bits = std::max(out.significant_bits, int(data[i]));
    } else if (type == "gAMA" && length == 4) {
      const uint32_t g = BigEndian32(data);  // light^(1/G) * 100000: 45455 for G = 2.2
      if (g > 0) out.gamma = std::round(100.0 * 100000.0 / g) / 100.0;
    }
  }
  return out;
}

}  // namespace lt

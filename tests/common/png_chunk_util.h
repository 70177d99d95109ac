// PNG chunks for tests: a chunk with its CRC, and adding one to a PNG file
// (sBIT, sRGB, gAMA: what OpenImageIO does not write), for tests of the image
// readers in every module (tests/common is on each test program's include path).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace lt::test {

// CRC-32 (ISO 3309), as PNG chunks use it.
inline uint32_t Crc32(const std::string& bytes) {
  uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

inline std::string BigEndian32(uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

// A PNG chunk with its CRC.
inline std::string Chunk(const std::string& type, const std::string& data) {
  const std::string td = type + data;
  return BigEndian32(uint32_t(data.size())) + td + BigEndian32(Crc32(td));
}

// Adds a chunk right after the IHDR of the PNG file at `path` (where sBIT,
// sRGB and gAMA belong: before PLTE and IDAT).
inline void InsertPngChunk(const std::filesystem::path& path, const std::string& type, const std::string& data) {
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    bytes = ss.str();
  }
  const size_t after_ihdr = 8 + 4 + 4 + 13 + 4;  // signature, then IHDR's length, type, data and CRC
  bytes.insert(after_ihdr, Chunk(type, data));
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

}  // namespace lt::test

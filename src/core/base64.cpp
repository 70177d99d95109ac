#include "core/base64.h"

namespace lt {

std::string Base64Encode(const uint8_t* data, size_t size) {
  static const char* kChars = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (size_t i = 0; i < size; i += 3) {
    uint32_t n = uint32_t(data[i]) << 16;
    if (i + 1 < size) n |= uint32_t(data[i + 1]) << 8;
    if (i + 2 < size) n |= data[i + 2];
    out += kChars[(n >> 18) & 63];
    out += kChars[(n >> 12) & 63];
    out += i + 1 < size ? kChars[(n >> 6) & 63] : '=';
    out += i + 2 < size ? kChars[n & 63] : '=';
  }
  return out;
}

}  // namespace lt

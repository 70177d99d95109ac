// Base64 encoding (RFC 4648, with padding) for data URIs: embedded glTF
// buffers, images inlined in HTML reports.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace lt {

std::string Base64Encode(const uint8_t* data, size_t size);

}  // namespace lt

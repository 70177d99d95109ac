#include "scene/gltf_container.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <vector>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/json_reader.h"
#include "scene/gltf_schema.h"
#include "scene/gltf_uri.h"

namespace lt {

namespace {

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

uint32_t ReadU32(const std::vector<unsigned char>& b, size_t offset) {
  uint32_t v;
  std::memcpy(&v, b.data() + offset, 4);  // GLB is little-endian, as is every supported host
  return v;
}


void AppendU32(std::vector<unsigned char>* out, uint32_t v) {
  const size_t at = out->size();
  out->resize(at + 4);
  std::memcpy(out->data() + at, &v, 4);  // little-endian, as ReadU32
}

// A GLB of the JSON text padded with spaces and the BIN payload padded with zeros.
std::vector<unsigned char> AlignedGlb(const std::string& json, const unsigned char* bin, size_t bin_length,
                                      bool has_bin) {
  const size_t json_padded = (json.size() + 3) / 4 * 4, bin_padded = (bin_length + 3) / 4 * 4;
  std::vector<unsigned char> out;
  out.reserve(20 + json_padded + (has_bin ? 8 + bin_padded : 0));
  AppendU32(&out, kGlbMagic);
  AppendU32(&out, 2);
  AppendU32(&out, uint32_t(20 + json_padded + (has_bin ? 8 + bin_padded : 0)));
  AppendU32(&out, uint32_t(json_padded));
  AppendU32(&out, kChunkJson);
  out.insert(out.end(), json.begin(), json.end());
  out.resize(20 + json_padded, ' ');
  if (has_bin) {
    AppendU32(&out, uint32_t(bin_padded));
    AppendU32(&out, kChunkBin);
    out.insert(out.end(), bin, bin + bin_length);
    out.resize(out.size() + bin_padded - bin_length, 0);
  }
  return out;
}

}  // namespace

std::string ShortenDataUris(const std::string& text, size_t keep) {
  std::string out;
  size_t pos = 0;
  while (true) {
    size_t at = text.find("data:", pos);
    if (at == std::string::npos) break;
    size_t end = at;
    while (end < text.size() && !std::isspace(static_cast<unsigned char>(text[end])) && text[end] != '"' &&
           text[end] != '\'' && text[end] != ']') {
      ++end;
    }
    out.append(text, pos, at - pos);
    if (end - at > keep + 3) {
      out.append(text, at, keep);
      out += "...";
    } else {
      out.append(text, at, end - at);
    }
    pos = end;
  }
  out.append(text, pos, std::string::npos);
  return out;
}

std::vector<unsigned char> ReadFileBytes(const std::filesystem::path& path, const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(file, "file not found (looked for " + path.string() + ")");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(file, "cannot open file (looked for " + path.string() + ")");
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  if (size < 0) throw InputError(file, "cannot read file " + path.string());
  if (uint64_t(size) > UINT32_MAX) throw InputError(file, "file is larger than 4 GiB, which glTF does not allow");
  std::vector<unsigned char> bytes(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size)) {
    throw InputError(file, "cannot read file " + path.string());
  }
  return bytes;
}

GltfContainer ParseGltfContainer(const std::vector<unsigned char>& bytes, const std::string& file) {
  GltfContainer c;
  if (bytes.size() < 4 || ReadU32(bytes, 0) != kGlbMagic) {
    if (bytes.empty()) throw InputError(file, "file is empty");
    // A JSON glTF starts with '{' (after an optional UTF-8 byte order mark and white space).
    size_t first = bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF ? 3 : 0;
    while (first < bytes.size() && std::strchr(" \t\r\n", bytes[first]) != nullptr && bytes[first] != 0) ++first;
    if (first == bytes.size() || bytes[first] != '{') {
      std::string head;
      for (size_t i = 0; i < 4 && i < bytes.size(); ++i) {
        static const char* kHex = "0123456789abcdef";
        head += std::string(i > 0 ? " " : "") + kHex[bytes[i] >> 4] + kHex[bytes[i] & 15];
      }
      throw InputError(file, "neither a GLB (bad magic: the first bytes are " + head +
                                 ", a GLB starts with \"glTF\" = 67 6c 54 46) nor JSON (which starts with '{')");
    }
    c.json_text.assign(bytes.begin(), bytes.end());
    c.total_length = bytes.size();
    return c;
  }
  c.binary = true;
  const size_t n = bytes.size();
  auto fail = [&](const std::string& m) -> void { throw InputError(file, "invalid GLB: " + m); };
  if (n < 20) fail("truncated: " + std::to_string(n) + " bytes, the header needs 20");
  uint32_t version = ReadU32(bytes, 4), length = ReadU32(bytes, 8);
  if (version == 1) {
    // glTF 1.0's binary glTF (KHR_binary_glTF): CesiumJS's older tiles, early exporters.
    fail("container version 1 (glTF 1.0's KHR_binary_glTF), only 2 is supported: upgrade the file to glTF 2.0 "
         "(gltf-pipeline -i in.glb -o out.glb does)");
  }
  if (version != 2) fail("container version " + std::to_string(version) + ", only 2 is supported");
  if (length > n) {
    fail("truncated: the header says " + std::to_string(length) + " bytes, the file has " + std::to_string(n));
  }
  if (length < 20) fail("header length " + std::to_string(length) + " is too small");
  uint64_t json_length = ReadU32(bytes, 12);
  if (ReadU32(bytes, 16) != kChunkJson) fail("the first chunk is not JSON");
  if (json_length == 0 || 20 + json_length > length) {
    fail("JSON chunk of " + std::to_string(json_length) + " bytes does not fit in " + std::to_string(length) + " bytes");
  }
  uint64_t end = 20 + json_length;
  uint64_t bin_length = 0;
  bool has_bin = false;
  if (end < length) {
    if (end + 8 > length) fail("truncated BIN chunk header");
    bin_length = ReadU32(bytes, size_t(end));
    has_bin = true;
    if (const uint32_t type = ReadU32(bytes, size_t(end) + 4); type != kChunkBin) {
      // Chunks of unknown types may only follow the first two (JSON, BIN).
      std::string name;
      for (int k = 0; k < 4; ++k) {
        const char ch = char((type >> (8 * k)) & 0xff);
        name += ch >= 0x20 && ch < 0x7f ? ch : '?';
      }
      char hex[16];
      std::snprintf(hex, sizeof hex, "0x%08x", type);
      fail(std::string("the second chunk is not BIN but of type ") + hex + " \"" + name +
           "\" (the BIN chunk must directly follow the JSON chunk; chunks of other types may only come after it)");
    }
    if (end + 8 + bin_length > length) {
      fail("BIN chunk of " + std::to_string(bin_length) + " bytes does not fit in the file (" +
           std::to_string(length - end - 8) + " bytes left)");
    }
  }
  c.json_text.assign(bytes.begin() + 20, bytes.begin() + static_cast<ptrdiff_t>(20 + json_length));
  c.total_length = length;
  c.has_bin = has_bin;
  c.bin_offset = size_t(end) + 8;
  c.bin_length = size_t(bin_length);
  // Chunks after the first two: of unknown types, glTF has them ignored; a second
  // BIN chunk is not glTF (buffer 0 is the first BIN chunk, and no buffer can name
  // another), so its bytes are not read: say so.
  std::string extra_bins;
  size_t extra_count = 0;
  for (uint64_t at = has_bin ? end + 8 + bin_length : end; at + 8 <= length;) {
    const uint64_t chunk_length = ReadU32(bytes, size_t(at));
    if (ReadU32(bytes, size_t(at) + 4) == kChunkBin) {
      ++extra_count;
      extra_bins += (extra_bins.empty() ? "" : ", ") + std::to_string(chunk_length) + " bytes at byte " +
                    std::to_string(at);
    }
    at += 8 + chunk_length;
  }
  if (json_length % 4 != 0 || bin_length % 4 != 0) {
    // Each chunk is where its length says; only the padding glTF asks for is missing.
    c.aligned = AlignedGlb(c.json_text, has_bin ? bytes.data() + c.bin_offset : nullptr, c.bin_length, has_bin);
    c.total_length = c.aligned.size();
    c.warning = "the GLB's chunks are not padded to 4 bytes as glTF asks (JSON chunk of " +
                std::to_string(json_length) + " bytes" +
                (has_bin ? ", BIN chunk of " + std::to_string(bin_length) + " bytes" : std::string()) +
                "); they are read as their lengths say";
  }
  if (extra_count > 0) {
    c.warning += std::string(c.warning.empty() ? "" : "; ") + (extra_count == 1 ? "a second BIN chunk" : std::to_string(extra_count) + " more BIN chunks") +
                 " (" + extra_bins + ") ignored: a GLB holds one BIN chunk (buffer 0); only the first is read";
  }
  return c;
}

void ReplaceGltfJson(GltfContainer* c, const std::vector<unsigned char>& bytes, std::string json) {
  c->json_text = std::move(json);
  if (!c->binary) {
    c->total_length = c->json_text.size();
    return;
  }
  c->aligned = AlignedGlb(c->json_text, c->has_bin ? bytes.data() + c->bin_offset : nullptr, c->bin_length, c->has_bin);
  c->total_length = c->aligned.size();
}

}  // namespace lt

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
constexpr size_t kMaxJsonDepth = 256;        // nested arrays and objects

uint32_t ReadU32(const std::vector<unsigned char>& b, size_t offset) {
  uint32_t v;
  std::memcpy(&v, b.data() + offset, 4);  // GLB is little-endian, as is every supported host
  return v;
}


// Number of bytes a base64 payload decodes to; fails on a character outside the
// base64 alphabet, padding before the end, or a length no encoder produces.
size_t Base64DecodedSize(const std::string& uri, size_t start, const std::string& where) {
  size_t chars = 0, padding = 0;
  for (size_t i = start; i < uri.size(); ++i) {
    const char c = uri[i];
    if (c == '=') {
      ++padding;
      continue;
    }
    const bool alphabet = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' || c == '/';
    if (!alphabet || padding > 0) {
      const unsigned char u = static_cast<unsigned char>(c);
      const std::string shown = u >= 0x20 && u < 0x7f ? std::string("'") + c + "'" : "byte " + std::to_string(u);
      throw InputError(where, "invalid base64 data: " + (padding > 0 ? "data after the '=' padding" : shown) +
                                  " at character " + std::to_string(i - start) + " of the data");
    }
    ++chars;
  }
  if (padding > 2 || chars % 4 == 1 || (padding > 0 && (chars + padding) % 4 != 0)) {
    throw InputError(where, "invalid base64 data: " + std::to_string(chars) + " characters and " +
                                std::to_string(padding) + " '=' is not a whole number of bytes");
  }
  return chars / 4 * 3 + (chars % 4 == 0 ? 0 : chars % 4 - 1);
}

// Checks a buffer's data: URI (tinygltf decodes only base64 with these media
// types, and needs exactly byteLength bytes).
void CheckBufferDataUri(const std::string& uri, const std::string& where, int64_t byte_length) {
  static const char* kHeaders[] = {"data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,"};
  size_t start = 0;
  for (const char* h : kHeaders) {
    if (uri.rfind(h, 0) == 0) start = std::strlen(h);
  }
  if (start == 0) {
    throw InputError(where, "a buffer's data URI must start with \"" + std::string(kHeaders[0]) + "\" or \"" +
                                kHeaders[1] + "\", got \"" + ShortenDataUris(uri) + "\"");
  }
  const size_t size = Base64DecodedSize(uri, start, where);
  if (byte_length >= 0 && size != uint64_t(byte_length)) {
    throw InputError(where, "data URI holds " + std::to_string(size) + " bytes, byteLength says " +
                                std::to_string(byte_length) + (size > uint64_t(byte_length) ? " (they must be equal)" : ""));
  }
}

// Fails when an external file named by uri does not exist (or is shorter than
// byte_length). Returns its normalized path and size, and enters it in `external`.
std::pair<std::filesystem::path, uint64_t> CheckExternal(const nlohmann::json& uri, const std::string& where,
                                                         const std::string& what,
                                                         const std::filesystem::path& base_dir, int64_t byte_length,
                                                         GltfExternalFiles* external) {
  if (!uri.is_string()) throw InputError(where, "uri must be a string");
  const std::string s = uri.get<std::string>();
  if (s.rfind("data:", 0) == 0) return {};
  if (s.empty()) throw InputError(where, "uri must not be empty");
  std::filesystem::path p = ResolveGltfUri(s, base_dir, where);
  if (external != nullptr) external->by_lookup_path[TinygltfLookupPath(s, base_dir.string())] = p;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(p, ec)) {
    throw InputError(where, what + " file not found (looked for " + p.string() + ")");
  }
  const uint64_t size = std::filesystem::file_size(p, ec);
  if (byte_length >= 0 && !ec && size < uint64_t(byte_length)) {
    throw InputError(where, what + " file " + p.string() + " has " + std::to_string(size) +
                                " bytes, byteLength says " + std::to_string(byte_length));
  }
  return {p, ec ? 0 : size};
}

// Fails when arrays and objects nest deeper than kMaxJsonDepth. tinygltf converts
// extras and extensions recursively, so a file nested 100 000 levels deep would
// overflow its stack; this scan (strings skipped) runs before any parser sees the text.
void CheckJsonDepth(const std::string& text, const std::string& file) {
  size_t depth = 0, line = 1, line_start = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    switch (c) {
      case '"': in_string = true; break;
      case '\n':
        ++line;
        line_start = i + 1;
        break;
      case '[':
      case '{':
        if (++depth > kMaxJsonDepth) {
          throw InputError(file + ":" + std::to_string(line) + ":" + std::to_string(i - line_start + 1),
                           "invalid glTF: JSON nesting depth exceeds the limit of " + std::to_string(kMaxJsonDepth) +
                               " levels");
        }
        break;
      case ']':
      case '}':
        if (depth > 0) --depth;
        break;
      default: break;
    }
  }
}

void AppendU32(std::vector<unsigned char>* out, uint32_t v) {
  unsigned char b[4];
  std::memcpy(b, &v, 4);
  out->insert(out->end(), b, b + 4);
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
  if (json_length % 4 != 0 || bin_length % 4 != 0) {
    // Each chunk is where its length says; only the padding glTF asks for is missing.
    const size_t bin_start = size_t(end) + 8;
    c.aligned = AlignedGlb(c.json_text, has_bin ? bytes.data() + bin_start : nullptr, size_t(bin_length), has_bin);
    c.total_length = c.aligned.size();
    c.warning = "the GLB's chunks are not padded to 4 bytes as glTF asks (JSON chunk of " +
                std::to_string(json_length) + " bytes" +
                (has_bin ? ", BIN chunk of " + std::to_string(bin_length) + " bytes" : std::string()) +
                "); they are read as their lengths say";
  }
  return c;
}

namespace {

// Whether a node's matrix places it as its translation / rotation / scale do
// (the identity for those not given), to about float precision. False when one
// of them is not an array of numbers of the right length (tinygltf reports it).
bool MatrixPlacesAsTrs(const nlohmann::json& node) {
  auto numbers = [&](const char* key, size_t count, std::vector<double> fallback) -> std::optional<std::vector<double>> {
    auto it = node.find(key);
    if (it == node.end()) return fallback;
    if (!it->is_array() || it->size() != count) return std::nullopt;
    std::vector<double> v;
    for (const auto& x : *it) {
      if (!x.is_number()) return std::nullopt;
      v.push_back(x.get<double>());
    }
    return v;
  };
  const auto m = numbers("matrix", 16, {});
  const auto t = numbers("translation", 3, {0, 0, 0});
  const auto r = numbers("rotation", 4, {0, 0, 0, 1});
  const auto s = numbers("scale", 3, {1, 1, 1});
  if (!m || !t || !r || !s) return false;
  Eigen::Matrix4d matrix;
  for (int c = 0; c < 4; ++c) {
    for (int k = 0; k < 4; ++k) matrix(k, c) = (*m)[size_t(4 * c + k)];
  }
  const Eigen::Quaterniond q((*r)[3], (*r)[0], (*r)[1], (*r)[2]);
  if (!(q.norm() > 1e-6)) return false;
  Eigen::Affine3d trs = Eigen::Translation3d((*t)[0], (*t)[1], (*t)[2]) * q.normalized() *
                        Eigen::Scaling((*s)[0], (*s)[1], (*s)[2]);
  const double scale = std::max({1.0, matrix.cwiseAbs().maxCoeff(), trs.matrix().cwiseAbs().maxCoeff()});
  return matrix.allFinite() && (matrix - trs.matrix()).cwiseAbs().maxCoeff() <= 1e-5 * scale;
}

}  // namespace

void CheckGltfJson(const GltfContainer& container, const std::string& file, const std::filesystem::path& base_dir,
                   GltfExternalFiles* external) {
  CheckJsonDepth(container.json_text, file);
  json::Document doc = json::Document::Parse(container.json_text, file, base_dir);
  const nlohmann::json& root = doc.Root().raw();
  if (!root.is_object()) throw InputError(file, "invalid glTF: the top level must be a JSON object");
  auto asset = root.find("asset");
  if (asset == root.end() || !asset->is_object()) throw InputError(file + ": /asset", "missing required object");
  auto version = asset->find("version");
  if (version == asset->end() || !version->is_string() || version->get<std::string>().rfind("2.", 0) != 0) {
    throw InputError(file + ": /asset/version",
                     "glTF version must be 2.x, got " + (version == asset->end() ? std::string("none") : version->dump()));
  }
  CheckGltfSchema(root, file);
  static const std::set<std::string> kSupported = {"KHR_materials_emissive_strength", "KHR_mesh_quantization",
                                                     "KHR_texture_transform", "EXT_mesh_gpu_instancing",
                                                     "KHR_materials_pbrSpecularGlossiness"};
  if (auto req = root.find("extensionsRequired"); req != root.end() && req->is_array()) {
    for (size_t i = 0; i < req->size(); ++i) {
      const auto& e = (*req)[i];
      if (!e.is_string() || kSupported.count(e.get<std::string>()) == 0) {
        // What to do about the extensions that optimising tools write.
        static const std::map<std::string, std::string> kHints = {
            {"KHR_draco_mesh_compression", "the meshes are Draco-compressed: write or convert the file without compression"},
            {"EXT_meshopt_compression", "the buffers are meshopt-compressed: write the file without it, e.g. gltfpack without -c/-cc"},
            {"KHR_texture_basisu", "the textures are KTX2: write or convert them as PNG or JPEG"},
            {"EXT_texture_webp", "the textures are WebP: write or convert them as PNG or JPEG"},
            {"EXT_texture_avif", "the textures are AVIF: write or convert them as PNG or JPEG"}};
        auto hint = e.is_string() ? kHints.find(e.get<std::string>()) : kHints.end();
        throw InputError(file + ": /extensionsRequired/" + std::to_string(i),
                         "required extension " + e.dump() + " is not supported" +
                             (hint != kHints.end() ? " (" + hint->second + ")" : std::string()));
      }
    }
  }
  // glTF gives a node a matrix or translation / rotation / scale, never both.
  // tinygltf reads the matrix and drops the rest, which is right when the rest
  // is the identity or places the node as the matrix does; otherwise the node
  // would be placed without it.
  if (auto nodes = root.find("nodes"); nodes != root.end() && nodes->is_array()) {
    for (size_t i = 0; i < nodes->size(); ++i) {
      const auto& n = (*nodes)[i];
      if (!n.is_object() || !n.contains("matrix")) continue;
      const char* key = nullptr;
      for (const char* k : {"translation", "rotation", "scale"}) {
        if (!key && n.contains(k)) key = k;
      }
      if (key && !MatrixPlacesAsTrs(n)) {
        throw InputError(file + ": /nodes/" + std::to_string(i),
                         std::string("has both a matrix and a ") + key +
                             " that place it differently (glTF gives a node one or the other: a matrix, or "
                             "translation / rotation / scale)");
      }
    }
  }
  if (auto buffers = root.find("buffers"); buffers != root.end() && buffers->is_array()) {
    for (size_t i = 0; i < buffers->size(); ++i) {
      const auto& b = (*buffers)[i];
      if (!b.is_object()) continue;  // tinygltf reports it
      auto uri = b.find("uri");
      if (uri == b.end()) {
        // Only a GLB's first buffer may omit uri: it is the BIN chunk. (tinygltf
        // would hand the BIN chunk to every buffer without uri.)
        if (container.binary && i == 0) continue;
        const bool fallback = b.contains("extensions") && b["extensions"].is_object() &&
                              b["extensions"].contains("EXT_meshopt_compression");
        throw InputError(file + ": /buffers/" + std::to_string(i),
                         fallback ? std::string("the buffer holds no data: it is the fallback buffer of "
                                                "EXT_meshopt_compression, whose compressed data is not supported "
                                                "(write the file without meshopt compression, e.g. gltfpack "
                                                "without -c/-cc)")
                                  : std::string("buffer has no uri") +
                                        (container.binary ? " (in a GLB only the first buffer, the BIN chunk, may "
                                                            "omit it)"
                                                          : " (a .gltf buffer needs one)"));
      }
      auto len = b.find("byteLength");
      int64_t byte_length = len != b.end() && len->is_number_unsigned() ? int64_t(len->get<uint64_t>()) : -1;
      const std::string where = file + ": /buffers/" + std::to_string(i) + "/uri";
      if (uri->is_string() && uri->get_ref<const std::string&>().rfind("data:", 0) == 0) {
        CheckBufferDataUri(uri->get_ref<const std::string&>(), where, byte_length);
      } else {
        auto [path, size] = CheckExternal(*uri, where, "buffer", base_dir, byte_length, external);
        if (external != nullptr && byte_length >= 0 && size > uint64_t(byte_length)) {
          // Two buffers naming one file with different lengths: left to tinygltf to refuse.
          auto [it, added] = external->buffer_lengths.emplace(path, uint64_t(byte_length));
          if (!added && it->second != uint64_t(byte_length)) it->second = size;
        }
      }
    }
  }
  // A Draco-compressed primitive that is not required may keep uncompressed
  // attributes as a fallback; its accessors without a bufferView are placeholders
  // (zeros to a reader without Draco), so such a primitive cannot be read.
  auto accessors = root.find("accessors");
  auto has_data = [&](const nlohmann::json& index) {
    if (!index.is_number_unsigned() || accessors == root.end() || !accessors->is_array() ||
        index.get<uint64_t>() >= accessors->size()) {
      return true;  // a dangling reference is reported later, where it is read
    }
    const auto& a = (*accessors)[index.get<size_t>()];
    return !a.is_object() || a.contains("bufferView") || a.contains("sparse");
  };
  if (auto meshes = root.find("meshes"); meshes != root.end() && meshes->is_array()) {
    for (size_t mi = 0; mi < meshes->size(); ++mi) {
      const auto& mesh = (*meshes)[mi];
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      const auto& prims = mesh["primitives"];
      for (size_t pi = 0; pi < prims.size(); ++pi) {
        const auto& p = prims[pi];
        if (!p.is_object() || !p.contains("extensions") || !p["extensions"].is_object() ||
            !p["extensions"].contains("KHR_draco_mesh_compression")) {
          continue;
        }
        std::vector<std::pair<std::string, nlohmann::json>> refs;
        if (p.contains("indices")) refs.emplace_back("indices", p["indices"]);
        if (p.contains("attributes") && p["attributes"].is_object()) {
          for (const auto& [name, index] : p["attributes"].items()) refs.emplace_back("attributes/" + name, index);
        }
        for (const auto& [name, index] : refs) {
          if (!has_data(index)) {
            throw InputError(file + ": /meshes/" + std::to_string(mi) + "/primitives/" + std::to_string(pi),
                             "compressed with KHR_draco_mesh_compression, which is not supported, and accessor " +
                                 index.dump() + " (its " + name +
                                 ") has no uncompressed data to fall back on (no bufferView); write the file "
                                 "without Draco");
          }
        }
      }
    }
  }
  if (auto images = root.find("images"); images != root.end() && images->is_array()) {
    for (size_t i = 0; i < images->size(); ++i) {
      const auto& im = (*images)[i];
      if (!im.is_object()) continue;
      auto uri = im.find("uri");
      if (uri == im.end()) continue;
      CheckExternal(*uri, file + ": /images/" + std::to_string(i) + "/uri", "texture image", base_dir, -1,
                    external);
    }
  }
}

}  // namespace lt

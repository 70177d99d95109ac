#include "scene/gltf_json_data.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "core/base64.h"
#include "core/error.h"
#include "scene/gltf_container.h"
#include "scene/gltf_uri.h"

namespace lt {

namespace {

// ASCII whitespace, which a data: URL's base64 may hold (lines) and decoders skip.
bool IsAsciiWhitespace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f'; }
bool IsAsciiUpper(char c) { return c >= 'A' && c <= 'Z'; }
char ToLowerAscii(char c) { return IsAsciiUpper(c) ? char(c - 'A' + 'a') : c; }
bool SameIgnoringCase(char c, char lower) { return ToLowerAscii(c) == lower; }
bool IsBase64Char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' || c == '/' || c == '=';
}

// Number of bytes a base64 payload decodes to, whitespace skipped; fails on a
// character outside the base64 alphabet, padding before the end, or a length no
// encoder produces (positions count the data as written).
size_t Base64DecodedSize(const std::string& uri, size_t start, const std::string& where) {
  size_t chars = 0, padding = 0;
  for (size_t i = start; i < uri.size(); ++i) {
    const char c = uri[i];
    if (IsAsciiWhitespace(c)) continue;
    if (c == '=') {
      ++padding;
      continue;
    }
    if (!IsBase64Char(c) || padding > 0) {
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

size_t DataUriHeader(const std::string& s);
bool IsBase64Header(const std::string& s, size_t header);

// Checks a buffer's data: URI (tinygltf decodes only base64 with these media
// types, and needs exactly byteLength bytes).
void CheckBufferDataUri(const std::string& uri, const std::string& where, int64_t byte_length) {
  static const char* kHeaders[] = {"data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,"};
  size_t start = 0;
  for (const char* h : kHeaders) {
    if (uri.rfind(h, 0) == 0) start = std::strlen(h);
  }
  const size_t header = DataUriHeader(uri);
  if (start == 0 && header > 0 && !IsBase64Header(uri, header)) {
    // RFC 2397's percent-encoded data, which glTF allows for images but not buffers.
    throw InputError(where, "a buffer's data URI must hold base64 (\";base64,\" before the data, as glTF embeds "
                            "buffers), got \"" + ShortenDataUris(uri) + "\"");
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
  if (s.size() >= 5 && std::equal(s.begin(), s.begin() + 5, "data:", SameIgnoringCase)) {
    if (s.find(',') == std::string::npos) {
      throw InputError(where, "a data: URI needs a ',' between its header and its data, got \"" + ShortenDataUris(s) + "\"");
    }
    return {};  // read by tinygltf (normalized by NormalizeDataUris)
  }
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

constexpr const char* kDataSections[] = {"buffers", "images"};

// The length of a data: URI's header, "data:" through the comma, written in any
// case (URI schemes and media types are case-insensitive); 0 for another uri.
size_t DataUriHeader(const std::string& s) {
  if (s.size() < 5 || !std::equal(s.begin(), s.begin() + 5, "data:", SameIgnoringCase)) return 0;
  const size_t comma = s.find(',');
  return comma == std::string::npos ? 0 : comma + 1;
}

// The item's uri if it is a data: URI, with its header's length.
std::pair<const std::string*, size_t> DataUri(const nlohmann::json& item) {
  if (!item.is_object()) return {nullptr, 0};
  auto uri = item.find("uri");
  if (uri == item.end() || !uri->is_string()) return {nullptr, 0};
  const std::string& s = uri->get_ref<const std::string&>();
  return {&s, DataUriHeader(s)};
}

bool IsBase64Header(const std::string& s, size_t header) {
  static const std::string kMarker = ";base64,";
  return header >= kMarker.size() + 5 &&
         std::equal(s.begin() + std::ptrdiff_t(header - kMarker.size()), s.begin() + std::ptrdiff_t(header),
                    kMarker.begin(), SameIgnoringCase);
}

// Whether a base64 data: URI's data holds whitespace and otherwise only base64
// characters (other data is left as written, for the check to name its place).
bool WrappedBase64(const std::string& s, size_t header) {
  if (!IsBase64Header(s, header)) return false;
  const auto data = s.begin() + std::ptrdiff_t(header);
  return std::any_of(data, s.end(), IsAsciiWhitespace) &&
         std::all_of(data, s.end(), [](char c) { return IsBase64Char(c) || IsAsciiWhitespace(c); });
}

// RFC 2397's data without ";base64": percent-encoded octets, decoded as browsers
// decode a data: URL (WHATWG fetch): '%' and two hex digits is that byte; anything
// else, a '%' not followed by two hex digits included, stands for itself.
// The same decoding as a file URI's (DecodeUri, scene/gltf_uri.h).
std::vector<uint8_t> PercentDecoded(const std::string& s, size_t start) {
  const std::string decoded = DecodeUri(s.substr(start));
  return std::vector<uint8_t>(decoded.begin(), decoded.end());
}

// The media type of a data: URI's header without its parameters ("image/png" of
// "data:image/png;charset=utf-8;base64,").
std::string MediaType(const std::string& s, size_t header) {
  const std::string media = s.substr(5, header - 6);  // between "data:" and the comma
  return media.substr(0, media.find(';'));
}

// A buffer's base64 data: URI of glTF's media type with parameters before ";base64,"
// (`application/octet-stream;charset=binary`): RFC 2397's mediatype holds parameters,
// and glTF-Validator and browsers read the type without them. tinygltf wants the
// bare header.
bool BufferWithParameters(const std::string& s, size_t header) {
  if (!IsBase64Header(s, header)) return false;
  std::string type = MediaType(s, header);
  std::transform(type.begin(), type.end(), type.begin(), ToLowerAscii);
  return (type == "application/octet-stream" || type == "application/gltf-buffer") &&
         header > 5 + type.size() + std::strlen(";base64,");
}

// `image`: an item of "images", else of "buffers".
bool NeedsNormalizing(const nlohmann::json& item, bool image) {
  const auto [s, header] = DataUri(item);
  if (header == 0) return false;
  if (image ? !IsBase64Header(*s, header) : BufferWithParameters(*s, header)) return true;
  return std::any_of(s->begin(), s->begin() + std::ptrdiff_t(header), IsAsciiUpper) || WrappedBase64(*s, header);
}

}  // namespace

bool DataUrisNeedNormalizing(const nlohmann::json& root) {
  if (!root.is_object()) return false;
  for (const char* section : kDataSections) {
    auto items = root.find(section);
    if (items == root.end() || !items->is_array()) continue;
    const bool image = std::strcmp(section, "images") == 0;
    if (std::any_of(items->begin(), items->end(), [&](const nlohmann::json& item) { return NeedsNormalizing(item, image); })) {
      return true;
    }
  }
  return false;
}

bool NormalizeDataUris(nlohmann::json* root) {
  if (!root->is_object()) return false;
  bool any = false;
  for (const char* section : kDataSections) {
    auto items = root->find(section);
    if (items == root->end() || !items->is_array()) continue;
    const bool image = std::strcmp(section, "images") == 0;
    for (nlohmann::json& item : *items) {
      if (!NeedsNormalizing(item, image)) continue;
      std::string& s = item["uri"].get_ref<std::string&>();
      const size_t header = DataUriHeader(s);
      std::transform(s.begin(), s.begin() + std::ptrdiff_t(header), s.begin(), ToLowerAscii);
      if (WrappedBase64(s, header)) {
        s.erase(std::remove_if(s.begin() + std::ptrdiff_t(header), s.end(), IsAsciiWhitespace), s.end());
      }
      if (image && !IsBase64Header(s, header)) {
        // Percent-encoded: as base64 (an image is decoded by its content, whatever its type).
        const std::vector<uint8_t> bytes = PercentDecoded(s, header);
        s = "data:application/octet-stream;base64," + Base64Encode(bytes.data(), bytes.size());
      } else if (!image && BufferWithParameters(s, header)) {
        s = "data:" + MediaType(s, header) + ";base64," + s.substr(header);
      }
      any = true;
    }
  }
  return any;
}

void CheckGltfBufferData(const nlohmann::json& root, bool binary, const std::string& file,
                         const std::filesystem::path& base_dir, GltfExternalFiles* external) {
  if (auto buffers = root.find("buffers"); buffers != root.end() && buffers->is_array()) {
    for (size_t i = 0; i < buffers->size(); ++i) {
      const auto& b = (*buffers)[i];
      if (!b.is_object()) continue;  // tinygltf reports it
      auto uri = b.find("uri");
      if (uri == b.end()) {
        // Only a GLB's first buffer may omit uri: it is the BIN chunk. (tinygltf
        // would hand the BIN chunk to every buffer without uri.)
        if (binary && i == 0) continue;
        // gltfpack 1.0 writes the ratified KHR_meshopt_compression, earlier ones the EXT_.
        std::string meshopt;
        for (const char* name : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
          if (b.contains("extensions") && b["extensions"].is_object() && b["extensions"].contains(name)) meshopt = name;
        }
        throw InputError(file + ": /buffers/" + std::to_string(i),
                         !meshopt.empty() ? "the buffer holds no data: it is the fallback buffer of " + meshopt +
                                                ", whose compressed data is not supported (write the file without "
                                                "meshopt compression, e.g. gltfpack without -c/-cc)"
                                  : std::string("buffer has no uri") +
                                        (binary ? " (in a GLB only the first buffer, the BIN chunk, may "
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
}

void CheckGltfImageFiles(const nlohmann::json& root, const std::string& file, const std::filesystem::path& base_dir,
                         const std::vector<bool>& read, GltfExternalFiles* external) {
  std::vector<std::pair<std::string, std::filesystem::path>> unread;  // (lookup path, file)
  if (auto images = root.find("images"); images != root.end() && images->is_array()) {
    for (size_t i = 0; i < images->size(); ++i) {
      const auto& im = (*images)[i];
      if (!im.is_object()) continue;
      auto uri = im.find("uri");
      if (uri == im.end()) continue;
      const std::string where = file + ": /images/" + std::to_string(i) + "/uri";
      if (i < read.size() && read[i]) {
        CheckExternal(*uri, where, "texture image", base_dir, -1, external);
        continue;
      }
      // Not read: tinygltf still asks for the file, and gets a placeholder for it.
      if (!uri->is_string() || uri->get_ref<const std::string&>().rfind("data:", 0) == 0) continue;
      const std::string& s = uri->get_ref<const std::string&>();
      std::filesystem::path p;
      try {
        p = ResolveGltfUri(s, base_dir, where);
      } catch (const InputError&) {  // a remote or malformed uri: never read, so never refused
        p = (base_dir / ("unread image " + std::to_string(i))).lexically_normal();
      }
      unread.emplace_back(TinygltfLookupPath(s, base_dir.string()), p);
    }
  }
  if (external == nullptr) return;
  // A file that a buffer or a read image also names is read for them.
  std::set<std::filesystem::path> read_files;
  for (const auto& entry : external->by_lookup_path) read_files.insert(entry.second);
  for (auto& [lookup, p] : unread) {
    external->by_lookup_path.emplace(lookup, p);
    if (read_files.count(p) == 0) external->unread_images.insert(p);
  }
}

}  // namespace lt

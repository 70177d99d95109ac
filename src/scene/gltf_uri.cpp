#include "scene/gltf_uri.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/text_fields.h"

namespace lt {

namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// The scheme of a URI (RFC 3986: a letter, then letters, digits, '+', '-' or
// '.', then ':'), lower case; empty for a relative reference or a one-letter
// "scheme", a Windows drive.
std::string SchemeOf(const std::string& uri) {
  size_t i = 0;
  while (i < uri.size() && (std::isalpha(static_cast<unsigned char>(uri[i])) ||
                            (i > 0 && (std::isdigit(static_cast<unsigned char>(uri[i])) || uri[i] == '+' ||
                                       uri[i] == '-' || uri[i] == '.')))) {
    ++i;
  }
  if (i < 2 || i >= uri.size() || uri[i] != ':') return {};
  return Lower(std::string_view(uri).substr(0, i));
}

}  // namespace

std::filesystem::path ResolveGltfUri(const std::string& uri, const std::filesystem::path& base_dir,
                                     const std::string& where) {
  const std::string scheme = SchemeOf(uri);
  if (scheme.empty()) return FindExportedFile((base_dir / DecodeUri(uri)).lexically_normal());
  if (scheme != "file") {
    throw InputError(where, "\"" + uri.substr(0, 80) + (uri.size() > 80 ? "...\"" : "\"") + " is a " + scheme +
                                ": URI; only local files are read (download it next to the glTF file and name it "
                                "by a relative uri)");
  }
  std::string rest = uri.substr(5);
  if (rest.rfind("//", 0) == 0) {  // file://host/path
    const size_t slash = rest.find('/', 2);
    const std::string host = rest.substr(2, slash == std::string::npos ? std::string::npos : slash - 2);
    if (!host.empty() && host != "localhost") {
      throw InputError(where, "\"" + uri + "\" names a file on host \"" + host + "\"; only local files are read");
    }
    rest = slash == std::string::npos ? std::string() : rest.substr(slash);
  }
  if (rest.empty() || rest[0] != '/') throw InputError(where, "\"" + uri + "\" is not an absolute file: URI");
  return FindExportedFile(std::filesystem::path(DecodeUri(rest)).lexically_normal());
}

std::string TinygltfLookupPath(const std::string& uri, const std::string& base_dir) {
  std::string decoded;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      decoded += ' ';
    } else if (uri[i] == '%' && uri.size() > i + 2) {
      // As tinygltf: a digit that is not hexadecimal counts as 0.
      decoded += char(std::max(HexValue(uri[i + 1]), 0) * 16 + std::max(HexValue(uri[i + 2]), 0));
      i += 2;
    } else {
      decoded += uri[i];
    }
  }
  if (base_dir.empty()) return decoded;
  return base_dir + (base_dir.back() == '/' ? "" : "/") + decoded;
}

std::string DecodeUri(const std::string& uri) {
  std::string out;
  out.reserve(uri.size());
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && HexValue(uri[i + 1]) >= 0 && HexValue(uri[i + 2]) >= 0) {
      out += char(HexValue(uri[i + 1]) * 16 + HexValue(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

}  // namespace lt

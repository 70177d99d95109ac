#include "scene/gltf_uri.h"

#include <algorithm>
#include <cctype>

namespace lt {

namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::filesystem::path FindExportedFile(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return path;
  fs::path wanted = path;
  if (std::string s = path.string(); s.find('\\') != std::string::npos) {
    std::replace(s.begin(), s.end(), '\\', '/');
    wanted = fs::path(s).lexically_normal();
    if (fs::is_regular_file(wanted, ec)) return wanted;
  }
  auto lower = [](std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  fs::path found = wanted.root_path();
  for (const fs::path& part : wanted.relative_path()) {
    fs::path next = found / part;
    if (part == "." || part == ".." || fs::exists(next, ec)) {
      found = next;
      continue;
    }
    const std::string name = lower(part.string());
    fs::path match;
    int matches = 0;
    for (fs::directory_iterator it(found.empty() ? fs::path(".") : found, ec), end; !ec && it != end; it.increment(ec)) {
      if (lower(it->path().filename().string()) == name) {
        match = found / it->path().filename();
        ++matches;
      }
    }
    if (matches != 1) return path;
    found = match;
  }
  return fs::is_regular_file(found, ec) ? found : path;
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

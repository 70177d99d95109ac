#include "core/file_lookup.h"

#include <algorithm>
#include <string>

#include "core/text_fields.h"

namespace lt {

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
  fs::path found = wanted.root_path();
  for (const fs::path& part : wanted.relative_path()) {
    fs::path next = found / part;
    if (part == "." || part == ".." || fs::exists(next, ec)) {
      found = next;
      continue;
    }
    const std::string name = Lower(part.string());
    fs::path match;
    int matches = 0;
    for (fs::directory_iterator it(found.empty() ? fs::path(".") : found, ec), end; !ec && it != end; it.increment(ec)) {
      if (Lower(it->path().filename().string()) == name) {
        match = found / it->path().filename();
        ++matches;
      }
    }
    if (matches != 1) return path;
    found = match;
  }
  return fs::is_regular_file(found, ec) ? found : path;
}

}  // namespace lt

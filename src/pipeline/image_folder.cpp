#include "pipeline/image_folder.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "core/error.h"
#include "core/text_fields.h"

namespace lt {

namespace fs = std::filesystem;

namespace {

bool IsDigit(char c) { return c >= '0' && c <= '9'; }

}  // namespace

const char* const kImageExtensionsText = ".png, .jpg, .jpeg, .tif, .tiff, .bmp, .pgm, .ppm, .pnm, .exr";

bool IsImageFile(const fs::path& p) {
  const std::string ext = Lower(p.extension().string());
  for (const char* e : {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".pgm", ".ppm", ".pnm", ".exr"}) {
    if (ext == e) return true;
  }
  return false;
}

bool NaturalLess(std::string_view a, std::string_view b) {

  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (IsDigit(a[i]) && IsDigit(b[j])) {
      size_t ie = i, je = j;
      while (ie < a.size() && IsDigit(a[ie])) ++ie;
      while (je < b.size() && IsDigit(b[je])) ++je;
      std::string_view na = a.substr(i, ie - i), nb = b.substr(j, je - j);
      while (na.size() > 1 && na.front() == '0') na.remove_prefix(1);
      while (nb.size() > 1 && nb.front() == '0') nb.remove_prefix(1);
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      i = ie, j = je;
      continue;
    }
    const char ca = char(std::tolower(static_cast<unsigned char>(a[i])));
    const char cb = char(std::tolower(static_cast<unsigned char>(b[j])));
    if (ca != cb) return ca < cb;
    ++i, ++j;
  }
  if ((i == a.size()) != (j == b.size())) return i == a.size();
  return a < b;
}

std::vector<fs::path> ImageFilesIn(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return {};
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (!name.empty() && name.front() != '.' && e.is_regular_file(ec) && IsImageFile(e.path())) files.push_back(e.path());
  }
  if (ec) throw InputError(folder.string(), "cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end(), [](const fs::path& x, const fs::path& y) {
    const auto tx = ParseFiniteNumber(x.stem().string()), ty = ParseFiniteNumber(y.stem().string());
    if (tx && ty && *tx != *ty) return *tx < *ty;
    return NaturalLess(x.filename().string(), y.filename().string());
  });
  return files;
}

std::vector<fs::path> ListImageFiles(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) throw InputError(folder.string(), "no such folder");
  if (!fs::is_directory(folder, ec)) throw InputError(folder.string(), "not a folder");
  std::vector<fs::path> files = ImageFilesIn(folder);
  if (files.empty()) {
    throw InputError(folder.string(), std::string("no image files in the folder (") + kImageExtensionsText +
                                          "), and no manifest.jsonl of a run");
  }
  return files;
}

}  // namespace lt

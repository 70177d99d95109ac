// The image files of a folder, as a camera's software, a phone or a scanner
// writes them: one listing for a capture without a manifest (`scan DIR`) and a
// folder of calibration photographs (`calibrate camera DIR`).
//   - extensions .png .jpg .jpeg .tif .tiff .bmp .pgm .ppm .pnm .exr, any case;
//   - hidden files (".name", macOS's "._name" copies) and sub-folders left out;
//   - natural order: runs of digits compare as numbers (img2 before img10),
//     other characters case-insensitively; names that are numbers (times such
//     as "1305031102.2" and "1305031102.175304") by value.
#pragma once

#include <filesystem>
#include <string_view>
#include <vector>

namespace lt {

// The extensions above, for messages: ".png, .jpg, ..., .exr".
extern const char* const kImageExtensionsText;

bool IsImageFile(const std::filesystem::path& p);

// Natural order of file names; ties ("img01", "img1") by bytes, so a total order.
bool NaturalLess(std::string_view a, std::string_view b);

// The folder's image files in the order above; empty when it is no folder or
// holds none.
std::vector<std::filesystem::path> ImageFilesIn(const std::filesystem::path& folder);

// The same, but an lt::InputError naming the folder when it does not exist, is
// not a folder, or holds no image file.
std::vector<std::filesystem::path> ListImageFiles(const std::filesystem::path& folder);

}  // namespace lt

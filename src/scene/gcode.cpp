// ParseGcode and ReadGcode: the file's kind, its lines and their ends, and the
// toolpath at its end. The reader's parts: a line's words in scene/gcode_line.cpp,
// its commands in gcode_commands.cpp, comments in gcode_comments.cpp, moves in
// gcode_moves.cpp and firmware retraction in gcode_retraction.cpp.
#include "scene/gcode.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "scene/gcode_reader.h"
#include "core/text_fields.h"

namespace lt {
namespace gcode_detail {

void GcodeReader::WarnBlobsInLayers() {
  // A start script's prime or purge in place (outside the layers) is expected; within
  // the layers a blob is on the part, where the beads leave it out.
  ToolpathWarning blobs;
  double laid_mm = 0;
  for (const ToolpathSegment& s : path_.segments) {
    if (!s.LaysBlob() || s.layer == ToolpathSegment::kNoLayer) continue;
    if (blobs.count++ == 0) blobs.line = s.line;
    laid_mm += s.laid_m / kMetresPerMm;
  }
  if (blobs.count == 0) return;
  char mm[32];
  std::snprintf(mm, sizeof mm, "%.3f", laid_mm);
  blobs.text = "filament fed in place (no X/Y motion) beyond what makes up a retraction, within a layer: a blob, "
               "which the part's beads leave out (a bead needs a path; the blob's shape is the material's and the "
               "surface's, not the file's); ";
  blobs.text.append(mm);
  blobs.text += " mm in all, in the filament laid in place";
  // Warnings stay in the order of their first lines.
  auto at = std::upper_bound(path_.warnings.begin(), path_.warnings.end(), blobs.line,
                             [](int line, const ToolpathWarning& w) { return line < w.line; });
  path_.warnings.insert(at, blobs);
}

Toolpath GcodeReader::Finish() {
  if (!layer_comments_) LayersFromZ();
  // The extra axes' warning names every one the file moved, not just the first line's.
  if (warning_index_[kExtraAxes] >= 0) path_.warnings[size_t(warning_index_[kExtraAxes])].text = ExtraAxesWarning(extra_axes_seen_);
  // Moves without E under M101 are the 3D form's only in a file that never gives E.
  if (warning_index_[kExtruderOnWithoutE] >= 0 && e_word_seen_) {
    path_.warnings.erase(path_.warnings.begin() + warning_index_[kExtruderOnWithoutE]);
    warning_index_[kExtruderOnWithoutE] = -1;
  }
  WarnBlobsInLayers();  // last: it inserts a warning, after which warning_index_ is stale
  return std::move(path_);
}

}  // namespace gcode_detail

using gcode_detail::ExtruderAxes;
using gcode_detail::GcodeReader;
using gcode_detail::StartsWith;

namespace {

// Where the line from `pos` ends: at LF, CR (of CR LF or a lone CR) or the text's end.
// Two memchr searches (a search for either byte was 15 % of a 44 MB file's parse); the
// next LF is remembered, so a file of lone CRs is not searched to its end per line.
class LineEnds {
 public:
  explicit LineEnds(std::string_view text) : text_(text) {}
  size_t From(size_t pos) {
    if (next_lf_ == std::string_view::npos || next_lf_ < pos) {
      const void* lf = std::memchr(text_.data() + pos, '\n', text_.size() - pos);
      next_lf_ = lf ? size_t(static_cast<const char*>(lf) - text_.data()) : text_.size();
    }
    const void* cr = std::memchr(text_.data() + pos, '\r', next_lf_ - pos);
    return cr ? size_t(static_cast<const char*>(cr) - text_.data()) : next_lf_;
  }

 private:
  std::string_view text_;
  size_t next_lf_ = std::string_view::npos;  // the first LF at or after the last position asked (or the end)
};

// The lines whose first word may be a move (G..., or N... followed by one): room
// for their segments is made once, so a large file's toolpath is not copied as it
// grows (a 38 MB file of 1.2 M moves: peak memory 424 -> 243 MB).
size_t MoveLinesAtMost(std::string_view text) {
  size_t count = 0;
  LineEnds ends(text);
  for (size_t pos = 0; pos < text.size();) {
    while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\t')) ++pos;
    if (pos < text.size()) {
      const char c = text[pos];
      if (c == 'G' || c == 'g' || c == 'N' || c == 'n') ++count;
    }
    size_t end = ends.From(pos);
    if (end == text.size()) break;
    pos = end + 1;
  }
  return count;
}

// Whether the file states that it is for Klipper: a comment line ";FLAVOR:Klipper" or
// "; gcode_flavor = klipper" (PrusaSlicer's, SuperSlicer's and OrcaSlicer's config
// block, which PrusaSlicer writes at the file's end), anywhere in the text.
bool KlipperFlavour(std::string_view text) {
  // memmem (two-way search): string_view::find stops at every 'F' of the file's feed
  // words, 5 % of a 100 MB file's read.
  auto find = [&](std::string_view tag, size_t from) {
    const void* hit = memmem(text.data() + from, text.size() - from, tag.data(), tag.size());
    return hit ? size_t(static_cast<const char*>(hit) - text.data()) : std::string_view::npos;
  };
  for (std::string_view tag : {std::string_view("gcode_flavor = klipper"), std::string_view("FLAVOR:Klipper")}) {
    for (size_t at = find(tag, 0); at != std::string_view::npos; at = find(tag, at + 1)) {
      size_t start = at;
      while (start > 0 && (text[start - 1] == ' ' || text[start - 1] == '\t')) --start;
      if (start > 0 && text[start - 1] == ';') {
        size_t before = start - 1;
        while (before > 0 && (text[before - 1] == ' ' || text[before - 1] == '\t')) --before;
        if (before == 0 || text[before - 1] == '\n' || text[before - 1] == '\r') return true;
      }
    }
  }
  return false;
}

// The text's lines through one reader reading E, A and B as `axes` says; sets
// `called_for` (if given) to GcodeReader::CalledFor.
Toolpath ReadLines(std::string_view text, const std::string& display_name, ExtruderAxes axes,
                   ExtruderAxes* called_for) {
  GcodeReader reader(display_name, axes);
  if (KlipperFlavour(text)) reader.SetKlipper();
  size_t pos = StartsWith(text, "\xEF\xBB\xBF") ? 3 : 0;  // a UTF-8 byte order mark
  reader.ReserveSegments(MoveLinesAtMost(text.substr(pos)));
  int line_no = 0;
  int after_end = 0;
  LineEnds ends(text);
  while (pos < text.size()) {
    // A line ends at LF, CR LF or a lone CR (classic Mac OS), mixed as they come.
    size_t end = ends.From(pos);
    std::string_view line = text.substr(pos, end - pos);
    if (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n') ++end;
    ++line_no;
    if (!reader.Ended()) {
      reader.ReadLine(line, line_no);
    } else {
      // Lines after the program's end are not read; those holding more than blanks,
      // comments and "%" are counted.
      std::string_view code = TrimBlanks(line.substr(0, line.find(';')));
      if (!code.empty() && code != "%") ++after_end;
    }
    pos = end + 1;
  }
  if (called_for) *called_for = reader.CalledFor();
  Toolpath path = reader.Finish();
  path.lines_after_program_end = after_end;
  return path;
}

}  // namespace

Toolpath ParseGcode(std::string_view text, const std::string& display_name) {
  // PrusaSlicer's binary G-code (.bgcode, the default for some printers since 2.7)
  // starts with the magic "GCDE" and holds compressed blocks: not readable as text.
  if (StartsWith(text, "GCDE")) {
    throw InputError(display_name,
                     "is a binary G-code file (PrusaSlicer's .bgcode, which starts with \"GCDE\"): export text "
                     "G-code instead (PrusaSlicer: untick \"Supports binary G-code\" in the printer's settings)");
  }
  // A zip archive: Bambu Studio's and OrcaSlicer's sliced project (.gcode.3mf) holds the
  // G-code of each plate as Metadata/plate_N.gcode.
  if (StartsWith(text, "PK\x03\x04")) {
    throw InputError(display_name,
                     "is a zip archive, not G-code (Bambu Studio's and OrcaSlicer's .gcode.3mf hold each plate's "
                     "G-code as Metadata/plate_1.gcode, ...): extract the plate's .gcode file");
  }
  // UTF-16 (Windows editors' "Unicode"): every other byte is NUL.
  if (StartsWith(text, "\xFF\xFE") || StartsWith(text, "\xFE\xFF")) {
    throw InputError(display_name, "is UTF-16 text (it starts with a UTF-16 byte order mark): save it as UTF-8 or ASCII");
  }
  // FlashForge's .gx (FlashPrint): "xgcode 1.0\n\0", a 58-byte header of little-endian
  // fields, thumbnails (a BMP, on newer printers a PNG too), then the G-code text from
  // the offset at byte 0x18. The G-code is read; its lines are counted from its start.
  if (StartsWith(text, "xgcode 1.0\n")) {
    constexpr size_t kGxHeaderBytes = 58, kGxGcodeOffsetAt = 0x18;
    if (text.size() < kGxHeaderBytes) {
      throw InputError(display_name, "is a FlashForge .gx file whose 58-byte header is cut short (" +
                                         std::to_string(text.size()) + " bytes)");
    }
    uint32_t offset = 0;
    for (int b = 3; b >= 0; --b) offset = offset << 8 | static_cast<unsigned char>(text[kGxGcodeOffsetAt + size_t(b)]);
    if (offset < kGxHeaderBytes || offset > text.size()) {
      throw InputError(display_name, "is a FlashForge .gx file whose header puts the G-code at byte " +
                                         std::to_string(offset) + ", outside the file's " +
                                         std::to_string(text.size()) + " bytes long");
    }
    text = text.substr(offset);
  }
  // A and B named in a file that prints with E are not its extruders (a ring, a rotary
  // axis); E in a file that prints with A or B is the active tool's axis (MakerBot):
  // read again so.
  ExtruderAxes reread = ExtruderAxes::kSeparate;
  try {
    Toolpath path = ReadLines(text, display_name, ExtruderAxes::kSeparate, &reread);
    if (reread != ExtruderAxes::kSeparate) path = ReadLines(text, display_name, reread, nullptr);
    return path;
  } catch (const InputError&) {
    // The first read takes A and B for extruders, which can refuse a file that prints
    // with E before its moves say so (a rotary "A30 C45" read as extruding while C
    // turns). Read with A and B as axes: that reading stands if the whole file calls
    // for it; else the first read's error does.
    if (reread != ExtruderAxes::kSeparate) throw;  // the second reading failed
    ExtruderAxes called = ExtruderAxes::kSeparate;
    std::optional<Toolpath> path;
    try {
      path = ReadLines(text, display_name, ExtruderAxes::kABExtra, &called);
    } catch (const InputError&) {
    }
    if (!path || called != ExtruderAxes::kABExtra) throw;
    return std::move(*path);
  }
}

Toolpath ReadGcode(const std::filesystem::path& path, const std::string& display_name) {
  std::string name = display_name.empty() ? path.string() : display_name;
  return ParseGcode(ReadTextFile(path, name), name);
}

}  // namespace lt

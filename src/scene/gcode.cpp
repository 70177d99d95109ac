// The G-code reader's lines: a line's command and parameter words, checksums and
// the end of the file; then ParseGcode and ReadGcode. Comments, moves and firmware
// retraction are in scene/gcode_comments.cpp, gcode_moves.cpp and gcode_retraction.cpp.
#include "scene/gcode.h"

#include <cmath>
#include <cstring>
#include <string>
#include <string_view>

#include "scene/gcode_reader.h"
#include "scene/motion_text.h"

namespace lt {
namespace gcode_detail {

namespace {

bool IsLetter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
char Upper(char c) { return (c >= 'a' && c <= 'z') ? char(c - 'a' + 'A') : c; }
bool IsNumberChar(char c) { return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+'; }
bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Marlin's commands whose parameter is free text, a message or a file name (M23 select,
// M28 write, M30 delete, M32 and M33 files; M117 and M118 messages, M928 log): a '*' in
// the text is no checksum.
bool IsTextCommand(std::string_view code) {
  size_t pos = 0;
  while (pos < code.size() && IsBlank(code[pos])) ++pos;
  if (pos < code.size() && Upper(code[pos]) == 'N') {  // a line number first
    ++pos;
    while (pos < code.size() && IsNumberChar(code[pos])) ++pos;
    while (pos < code.size() && IsBlank(code[pos])) ++pos;
  }
  if (pos >= code.size() || Upper(code[pos]) != 'M') return false;
  int n = 0;
  size_t digits = 0;
  for (++pos; pos < code.size() && code[pos] >= '0' && code[pos] <= '9' && digits < 6; ++pos, ++digits) {
    n = 10 * n + (code[pos] - '0');
  }
  if (digits == 0 || (pos < code.size() && (code[pos] == '.' || (code[pos] >= '0' && code[pos] <= '9')))) return false;
  for (int text : {23, 28, 30, 32, 33, 117, 118, 928}) {
    if (n == text) return true;
  }
  return false;
}

// A checksum's digits: 1 to 3 of them between blanks.
bool IsChecksum(std::string_view text) {
  text = TrimBlanks(text);
  if (text.empty() || text.size() > 3) return false;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

}  // namespace

Toolpath GcodeReader::Finish() {
  if (!layer_comments_) LayersFromZ();
  return std::move(path_);
}

void GcodeReader::ReadWords(std::string_view code, size_t pos, bool numbers_required, bool t_parameter) {
  words_.clear();
  while (pos < code.size()) {
    if (IsBlank(code[pos])) {
      ++pos;
      continue;
    }
    char letter = Upper(code[pos]);
    if (!IsLetter(letter)) Fail("expected a parameter letter, got \"" + std::string(code.substr(pos)) + "\"");
    ++pos;
    size_t start = pos;
    while (pos < code.size() && IsNumberChar(code[pos])) ++pos;
    std::string_view number = code.substr(start, pos - start);
    if (pos < code.size() && code[pos] == ':' && !number.empty()) {
      Fail(std::string(1, letter) + " with several values (\"" + std::string(code.substr(start)) +
           "\": RepRapFirmware's amounts per drive) is not supported: write one value");
    }
    Word w;
    w.letter = letter;
    if (number.empty()) {
      std::string rest(code.substr(start, 3));
      for (char& ch : rest) ch = Upper(ch);
      if (rest == "NAN" || rest == "INF") Fail(std::string(1, letter) + " is not a finite number");
      if (numbers_required) Fail(std::string(1, letter) + " without a number");
    } else {
      w.value = ParseFiniteNumber(number);
      if (!w.value) Fail(std::string(1, letter) + " has a malformed number \"" + std::string(number) + "\"");
    }
    if (letter == 'G' || letter == 'M') {
      // Several commands on one line ("G21 G90", "G90 G94 G17"): each in turn.
      next_command_ = code.substr(start - 1);
      return;
    }
    if (letter == 'T' && !t_parameter) Fail("one command per line: found T after the command");
    for (const Word& other : words_) {
      if (other.letter == letter) Fail(std::string(1, letter) + " given twice");
    }
    words_.push_back(w);
  }
}

const Word* GcodeReader::Find(char letter) const {
  for (const Word& w : words_) {
    if (w.letter == letter) return &w;
  }
  return nullptr;
}

void GcodeReader::Expect(std::string_view allowed, const std::string& command) const {
  for (const Word& w : words_) {
    if (allowed.find(w.letter) == std::string_view::npos) {
      Fail(command + " takes no parameter " + std::string(1, w.letter));
    }
  }
}

void GcodeReader::CheckChecksum(std::string_view line, size_t star, size_t end) {
  std::string_view digits = TrimBlanks(line.substr(star + 1, end == std::string_view::npos ? end : end - star - 1));
  bool ok = !digits.empty() && digits.size() <= 3;
  for (char c : digits) ok = ok && c >= '0' && c <= '9';
  if (!ok) Fail("checksum after '*' must be a number 0-255, got \"" + std::string(digits) + "\"");
  int expected = std::stoi(std::string(digits));
  int sum = 0;
  for (char c : line.substr(0, star)) sum ^= static_cast<unsigned char>(c);
  if (sum != expected) {
    Fail("checksum *" + std::string(digits) + " does not match the line (its bytes before '*' give " +
         std::to_string(sum) + ")");
  }
}

void GcodeReader::ReadLine(std::string_view line, int line_no) {
  line_no_ = line_no;
  if (line.find('\0') != std::string_view::npos) Fail("a NUL byte: this is not a text G-code file");
  // One pass over the line: a parenthesised comment runs to its ')' (a ';' or '*'
  // inside it is part of the comment, as in RS-274 and Marlin's PAREN_COMMENTS), a
  // quoted string to its closing '"' (RepRapFirmware's M291 P"..." and file names);
  // outside them, ';' starts the line's comment and the first '*' its checksum.
  size_t semicolon = line.find(';'), star = std::string_view::npos;
  bool paren = false, inside = false, quoted = false;
  // Most lines hold neither '(' nor '"' before a ';': the searches suffice (the pass
  // over every character made a 44 MB file's parse 18 % slower).
  const std::string_view before = line.substr(0, semicolon);
  const bool plain = before.find('(') == std::string_view::npos && before.find('"') == std::string_view::npos;
  if (plain) star = before.find('*');
  semicolon = plain ? semicolon : std::string_view::npos;
  for (size_t i = 0; !plain && i < line.size(); ++i) {
    const char c = line[i];
    if (inside) {
      if (c == ')') inside = false;
    } else if (quoted || c == '"') {
      if (c == '"') quoted = !quoted;
    } else if (c == '(') {
      inside = true;
      paren = true;
    } else if (c == ';') {
      semicolon = i;
      break;
    } else if (c == '*' && star == std::string_view::npos) {
      star = i;
    }
  }
  std::string_view code = line.substr(0, semicolon);
  // A checksum "*57" ends the code; it must match (a corrupted line is not read). In
  // the text of a message or file name a '*' is text, unless only a checksum follows.
  if (star != std::string_view::npos &&
      (!IsTextCommand(code) || IsChecksum(line.substr(star + 1, semicolon == std::string_view::npos
                                                                    ? semicolon
                                                                    : semicolon - star - 1)))) {
    CheckChecksum(line, star, semicolon);
    code = code.substr(0, star);
  }
  std::string cleaned;
  if (paren) {
    inside = quoted = false;
    for (char c : code) {
      if (!inside && c == '"') quoted = !quoted;
      if (!quoted && c == '(') inside = true;
      if (!inside) cleaned += c;
      if (c == ')') inside = false;
    }
    code = cleaned;
  }
  code = TrimBlanks(code);
  if (code == "%") return;  // RS-274's program start and end mark
  if (code.empty()) {
    if (semicolon != std::string_view::npos) Comment(line.substr(semicolon + 1));
    return;
  }
  size_t pos = 0;
  // A line number "N123" first.
  if (Upper(code[0]) == 'N' && code.size() > 1 && code[1] >= '0' && code[1] <= '9') {
    ++pos;
    while (pos < code.size() && IsNumberChar(code[pos])) ++pos;
    while (pos < code.size() && IsBlank(code[pos])) ++pos;
    if (pos == code.size()) return;
  }
  ReadCommand(code, pos);
  while (!next_command_.empty()) {
    const std::string_view next = next_command_;
    next_command_ = {};
    ReadCommand(next, 0);
  }
}

void GcodeReader::ReadCommand(std::string_view code, size_t pos) {
  // An extended command (Klipper's PRINT_START, EXCLUDE_OBJECT_START NAME=...,
  // SET_PRESSURE_ADVANCE ADVANCE=...): a name of letters, digits and
  // underscores that does not start with a letter and a number. Skipped, counted by name.
  if (pos + 1 < code.size() && IsLetter(code[pos]) && (IsLetter(code[pos + 1]) || code[pos + 1] == '_')) {
    size_t end = pos;
    while (end < code.size() && !IsBlank(code[end])) ++end;
    std::string name(code.substr(pos, end - pos));
    for (char& ch : name) ch = Upper(ch);
    ++path_.skipped_commands[name];
    return;
  }
  char letter = Upper(code[pos]);
  if (letter != 'G' && letter != 'M' && letter != 'T') {
    Fail("expected a command (G, M or T), got \"" + std::string(code.substr(pos)) + "\"");
  }
  size_t start = ++pos;
  while (pos < code.size() && IsNumberChar(code[pos])) ++pos;
  std::string_view number = code.substr(start, pos - start);
  if (number.empty() && letter == 'T' && pos < code.size() && !IsBlank(code[pos])) {
    // Prusa firmware's MMU tool commands "Tx", "Tc", "T?": skipped, counted by name.
    std::string name = "T";
    for (; pos < code.size() && !IsBlank(code[pos]); ++pos) name += Upper(code[pos]);
    ++path_.skipped_commands[name];
    return;
  }
  if (number.empty()) Fail(std::string(1, letter) + " without a number");
  auto value = ParseFiniteNumber(number);
  if (!value) Fail(std::string(1, letter) + " has a malformed number \"" + std::string(number) + "\"");
  const bool integral = *value == std::floor(*value) && std::abs(*value) < 1e6;
  const int n = integral ? int(*value) : -1;
  if (letter == 'G' && integral) {
    switch (n) {
      case 0:
      case 1: ReadWords(code, pos, true); Move(n); return;
      case 2:
      case 3: ReadWords(code, pos, true); Arc(n); return;
      case 4: ReadWords(code, pos, true); Dwell(); return;
      case 5:
        // Skipped, the nozzle's path would go on from the curve's start: refused instead.
        Fail("G5 (Marlin's cubic Bezier move) is not supported: its path would be missing; write the curve as "
             "G1 or G2/G3 moves");
      case 10:
        ReadWords(code, pos, true);
        if (words_.empty()) {
          FirmwareRetract(true);
          return;
        }
        // With parameters: tool offsets and temperatures (RepRapFirmware's G10 P),
        // coordinate systems (G10 L), Marlin's swap retraction (G10 S1): skipped.
        ++path_.skipped_commands["G10"];
        return;
      case 11: ReadWords(code, pos, true); Expect("", "G11"); FirmwareRetract(false); return;
      case 17:
      case 18:
      case 19: ReadWords(code, pos, true); Expect("", CommandName('G', n)); xy_plane_ = n == 17; return;
      case 20:
      case 21: ReadWords(code, pos, true); Expect("", CommandName('G', n)); unit_mm_ = n == 20 ? 25.4 : 1.0; return;
      case 28: ReadWords(code, pos, false); Home(); return;
      case 90:
      case 91: ReadWords(code, pos, true); Expect("", CommandName('G', n)); xyz_relative_ = n == 91; return;
      case 92: ReadWords(code, pos, true); SetPosition(); return;
      default: break;
    }
  }
  if (letter == 'M' && (n == 2 || n == 30)) {
    // Program end (RS-274, RepRapFirmware, Klipper's M2-less world aside): nothing
    // after it runs. Marlin's "M30 name" deletes a file on the SD card: skipped.
    if (n == 30 && !TrimBlanks(code.substr(pos)).empty()) {
      ++path_.skipped_commands["M30"];
      return;
    }
    path_.program_end_line = line_no_;
    path_.program_end_command = CommandName('M', n);
    return;
  }
  if (letter == 'M' && n == 200) {
    ReadWords(code, pos, true, true);
    VolumetricExtrusion();
    return;
  }
  if (letter == 'M' && n == 207) {
    ReadWords(code, pos, true, true);
    RetractSettings();
    return;
  }
  if (letter == 'M' && (n == 82 || n == 83)) {
    ReadWords(code, pos, true);
    Expect("", CommandName('M', n));
    e_mode_ = n == 82 ? EMode::kAbsolute : EMode::kRelative;
    return;
  }
  std::string name(1, letter);
  name += integral ? std::to_string(n) : std::string(number);
  ++path_.skipped_commands[name];
}

}  // namespace gcode_detail

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
  GcodeReader reader(display_name);
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
  Toolpath path = reader.Finish();
  path.lines_after_program_end = after_end;
  return path;
}

Toolpath ReadGcode(const std::filesystem::path& path, const std::string& display_name) {
  std::string name = display_name.empty() ? path.string() : display_name;
  return ParseGcode(ReadTextFile(path, name), name);
}

}  // namespace lt

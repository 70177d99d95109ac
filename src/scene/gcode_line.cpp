// The G-code reader's lines: a line's comments (parenthesised, quoted, ';'), its
// checksum and line number, and the parameter words of its commands.
#include <string>
#include <string_view>

#include "scene/gcode_reader.h"
#include "core/text_fields.h"

namespace lt {
namespace gcode_detail {

namespace {

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

void GcodeReader::ReadWords(std::string_view code, size_t pos, bool numbers_required, bool t_parameter) {
  words_.clear();
  auto add = [&](const Word& w) {
    for (const Word& other : words_) {
      if (other.letter == w.letter) Fail(std::string(1, w.letter) + " given twice");
    }
    words_.push_back(w);
  };
  while (pos < code.size()) {
    if (IsBlank(code[pos])) {
      ++pos;
      continue;
    }
    char letter = Upper(code[pos]);
    if (!IsLetter(letter)) Fail("expected a parameter letter, got \"" + std::string(code.substr(pos)) + "\"");
    ++pos;
    size_t start = pos;
    if (pos < code.size() && code[pos] == '"') {
      // A quoted string: RepRapFirmware's file names ("G29 S1 P\"heightmap.csv\"", a ""
      // inside it one quote); a word without a number.
      for (++pos; pos < code.size(); ++pos) {
        if (code[pos] != '"') continue;
        if (pos + 1 < code.size() && code[pos + 1] == '"') {
          ++pos;
          continue;
        }
        break;
      }
      if (pos >= code.size()) Fail(std::string(1, letter) + " has a string without its closing '\"'");
      ++pos;
      add(Word{letter, std::nullopt});
      continue;
    }
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
      if (start < code.size() && code[start] == '{') {
        Fail(std::string(1, letter) + " is an expression (\"" + std::string(code.substr(start)) +
             "\": RepRapFirmware's meta commands, or a slicer placeholder left unfilled), not a number: the reader "
             "takes numbers only");
      }
      if (numbers_required) Fail(std::string(1, letter) + " without a number");
    } else {
      w.value = ParseFiniteNumber(number);
      if (!w.value) Fail(std::string(1, letter) + " has a malformed number \"" + std::string(number) + "\"");
    }
    if ((letter == 'G' || letter == 'M') && w.value) {
      // Several commands on one line ("G21 G90", "G90 G94 G17"): each in turn. A G
      // without a number is a parameter (Prusa's "G29 G": absorb the bed's heat).
      next_command_ = code.substr(start - 1);
      return;
    }
    if (letter == 'T' && !t_parameter) Fail("one command per line: found T after the command");
    add(w);
  }
}

std::vector<std::pair<std::string, std::string_view>> KeyValues(std::string_view params) {
  std::vector<std::pair<std::string, std::string_view>> out;
  size_t pos = 0;
  while (pos < params.size()) {
    while (pos < params.size() && IsBlank(params[pos])) ++pos;
    size_t end = pos;
    while (end < params.size() && !IsBlank(params[end])) ++end;
    const std::string_view word = params.substr(pos, end - pos);
    pos = end;
    const size_t eq = word.find('=');
    if (eq == std::string_view::npos) continue;
    std::string key(word.substr(0, eq));
    for (char& c : key) c = Upper(c);
    out.emplace_back(std::move(key), word.substr(eq + 1));
  }
  return out;
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
  // inside it is part of the comment, as in RS-274 and Marlin's PAREN_COMMENTS; a '('
  // inside it nests: Skeinforge's "(<setting> dimension Filament_Diameter_(mm): 1.75
  // </setting>)" is one comment, as MakerBot's print driver (s3g) counts them), a
  // quoted string to its closing '"' (RepRapFirmware's M291 P"..." and file names);
  // outside them, ';' starts the line's comment and the first '*' its checksum.
  size_t semicolon = line.find(';'), star = std::string_view::npos;
  bool paren = false, quoted = false;
  int depth = 0;  // of nested '(' comments
  size_t open_paren = 0;  // where the last '(' comment opened
  // Most lines hold neither '(' nor '"' before a ';': the searches suffice (the pass
  // over every character made a 44 MB file's parse 18 % slower).
  const std::string_view before = line.substr(0, semicolon);
  const bool plain = before.find('(') == std::string_view::npos && before.find('"') == std::string_view::npos;
  if (plain) star = before.find('*');
  semicolon = plain ? semicolon : std::string_view::npos;
  for (size_t i = 0; !plain && i < line.size(); ++i) {
    const char c = line[i];
    if (depth > 0) {
      depth += c == '(' ? 1 : c == ')' ? -1 : 0;
    } else if (quoted || c == '"') {
      if (c == '"') quoted = !quoted;
    } else if (c == '(') {
      depth = 1;
      paren = true;
      open_paren = i;
    } else if (c == ';') {
      semicolon = i;
      break;
    } else if (c == '*' && star == std::string_view::npos) {
      star = i;
    }
  }
  if (depth > 0) {
    // A '(' without ')' runs to the end of the line, as Marlin (PAREN_COMMENTS) and
    // RepRapFirmware read it; the words before it are read. Whether the writer meant
    // the rest as a comment is not certain: warned.
    std::string rest(TrimBlanks(line.substr(open_paren)));
    if (rest.size() > 40) rest = rest.substr(0, 37) + "...";
    Warn(kUnclosedParen, "a '(' comment without ')' runs to the end of its line, as Marlin and RepRapFirmware read it: \"" +
                             rest + "\" is not read");
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
    quoted = false;
    depth = 0;
    for (char c : code) {
      if (depth == 0 && c == '"') quoted = !quoted;
      if (!quoted && c == '(') ++depth;
      if (depth == 0) cleaned += c;
      if (c == ')' && depth > 0) --depth;
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
  commands_on_line_ = 0;
  machine_coordinates_ = false;
  ReadCommand(code, pos);
  while (!next_command_.empty()) {
    const std::string_view next = next_command_;
    next_command_ = {};
    ReadCommand(next, 0);
  }
}

}  // namespace gcode_detail
}  // namespace lt

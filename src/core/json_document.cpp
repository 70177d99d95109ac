// Document (core/json_reader.h): reading and parsing a JSON file into the DOM that
// Values point into, with syntax errors at file:line:column and repeated keys rejected.
// Value and Object are in json_reader.cpp.
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/json_context.h"
#include "core/json_reader.h"

namespace lt::json {

namespace {

// Line and column (1-based) of a byte offset in text.
std::pair<size_t, size_t> LineColumn(const std::string& text, size_t offset) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

// Builds the document as nlohmann's DOM parser does, following the events to know
// the JSON pointer of the value being read and the keys each open object has had:
// JSON leaves a repeated key's meaning open (nlohmann keeps the last), so a
// repeated key is an error. (A SAX handler, not a parse callback: nlohmann's
// callback parser scans the whole enclosing array at the end of every object, so
// an array of n objects took O(n^2), 14 s for a glTF file of 200 000 nodes.)
class DuplicateKeyCheck {
 public:
  using json = nlohmann::json;
  explicit DuplicateKeyCheck(json& root) : dom_(root, true) {}

  bool null() { return Completed(dom_.null()); }
  bool boolean(bool v) { return Completed(dom_.boolean(v)); }
  bool number_integer(json::number_integer_t v) { return Completed(dom_.number_integer(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return Completed(dom_.number_unsigned(v)); }
  bool number_float(json::number_float_t v, const json::string_t& s) { return Completed(dom_.number_float(v, s)); }
  bool string(json::string_t& v) { return Completed(dom_.string(v)); }
  bool binary(json::binary_t& v) { return Completed(dom_.binary(v)); }
  bool start_object(std::size_t n) {
    frames_.emplace_back().object = true;
    return dom_.start_object(n);
  }
  bool key(json::string_t& k) {
    Frame& f = frames_.back();
    f.key = k;
    if (!f.keys.insert(k).second && duplicate_.empty()) duplicate_ = Pointer();
    return dom_.key(k);
  }
  bool end_object() {
    frames_.pop_back();
    return Completed(dom_.end_object());
  }
  bool start_array(std::size_t n) {
    frames_.emplace_back();
    return dom_.start_array(n);
  }
  bool end_array() {
    frames_.pop_back();
    return Completed(dom_.end_array());
  }
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& token, const Exception& e) {
    return dom_.parse_error(position, token, e);  // throws e
  }
  const std::string& duplicate_pointer() const { return duplicate_; }
  // The pointer of the value being read (after its key or its array position).
  std::string current_pointer() const { return Pointer(); }

 private:
  struct Frame {
    bool object = false;
    std::set<std::string> keys;
    std::string key;
    size_t index = 0;
  };
  // A value inside an array was read: the next one has the next index.
  bool Completed(bool ok) {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
    return ok;
  }
  std::string Pointer() const {
    std::string p;
    for (const Frame& f : frames_) {
      p += '/';
      p += f.object ? EscapePointerToken(f.key) : std::to_string(f.index);
    }
    return p;
  }
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  std::vector<Frame> frames_;
  std::string duplicate_;
};

}  // namespace

// ---------------------------------------------------------------- Document

Value Document::Root() const { return Value(ctx_, &ctx_->root, ""); }

const std::string& Document::file() const { return ctx_->file; }

Document Document::Parse(const std::string& text, std::string display_name,
                         const std::filesystem::path& base_dir) {
  auto ctx = std::make_shared<Context>();
  ctx->file = std::move(display_name);
  ctx->base_dir = base_dir;
  DuplicateKeyCheck duplicates(ctx->root);
  try {
    nlohmann::json::sax_parse(text, &duplicates);
  } catch (const nlohmann::json::parse_error& e) {
    auto [line, col] = LineColumn(text, e.byte > 0 ? e.byte - 1 : 0);
    // nlohmann's message reads "[json.exception.parse_error.101] parse error at
    // line 3, column 8: syntax error while parsing ..."; keep the reason only.
    std::string msg = e.what();
    auto pos = msg.find(": ");
    if (msg.find("parse error") != std::string::npos && pos != std::string::npos) msg = msg.substr(pos + 2);
    throw InputError(ctx->file + ":" + std::to_string(line) + ":" + std::to_string(col),
                     "invalid JSON: " + msg);
  } catch (const nlohmann::json::exception& e) {  // e.g. a number too large for a double
    std::string msg = e.what();
    auto pos = msg.find("] ");
    if (pos != std::string::npos) msg = msg.substr(pos + 2);
    // Name the value (1e400, the only way to write an infinity, in "exposure_us").
    std::string where = ctx->file;
    const std::string pointer = duplicates.current_pointer();
    if (!pointer.empty()) {
      where += ": ";
      where += pointer;
    }
    throw InputError(where, "invalid JSON: " + msg);
  }
  if (!duplicates.duplicate_pointer().empty()) {
    const std::string& p = duplicates.duplicate_pointer();
    throw InputError(ctx->file + ": " + p, "key given twice (JSON leaves a repeated key's meaning open)");
  }
  Document d;
  d.ctx_ = std::move(ctx);
  return d;
}

Document Document::Load(const std::filesystem::path& path, std::string display_name) {
  if (display_name.empty()) display_name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(display_name, "cannot open file (looked for " + path.string() + ")");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(display_name, "cannot read file");
  std::filesystem::path base = path.parent_path();
  if (base.empty()) base = ".";
  return Parse(ss.str(), display_name, base);
}

}  // namespace lt::json

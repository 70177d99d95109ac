// The scalars of the YAML tree (pipeline/yaml_tree.h): comments, quoted
// scalars and the text of block scalars, as one line of YAML holds them; and
// the typed reads of a scalar value (number, integer, string) with their
// errors, which every calibration-file reader uses (OpenCV's entries,
// pipeline/opencv_yaml.h, and the nodes of other tools' camera files,
// pipeline/camera_file_formats.h).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace lt {

// Whether s[i] opens a quoted scalar: a quote where a value or key can start.
bool OpensYamlQuote(const std::string& s, size_t i);

// Whether every [ and { of a flow collection's text is closed (outside quotes),
// as the text grows by the lines the collection spans: each call goes on from
// where the last one stopped, so n lines cost their length once, not n times.
class FlowBalance {
 public:
  // `s` is the text of the last call with more appended. True when every bracket
  // is closed; false while some are open, or (*extra set to it) when a ] or }
  // closes nothing.
  bool Closed(const std::string& s, char* extra);

 private:
  size_t pos_ = 0;     // the next character to look at
  size_t search_ = 0;  // where to look on for the closing quote of a quote at pos_
  int depth_ = 0;
};

// `s` without its `#` comment (one at the start or after a blank, outside quotes).
std::string StripYamlComment(const std::string& s);

// The quoted scalar ("double": \n, \t, and \c for any other c; 'single': '' for ') whose
// quote is s[begin], unquoted into *value; *end is just past its closing
// quote. False when it is not closed on this text.
bool ReadQuotedScalar(const std::string& s, size_t begin, std::string* value, size_t* end);

// The value of a block scalar from its lines (their common indentation
// removed, blank lines empty): literal (style '|') or folded ('>'), with its
// chomping ('-' strip, '+' keep, 0 clip: one final line break).
std::string BlockScalarText(const std::vector<std::string>& lines, char style, char chomp);

// A value to read as a number, an integer or a string: its text when it is a
// scalar (nullptr for a collection, another type or nothing), whether it was
// quoted (a string, never a number), and its name and place ("file:line") for
// the errors.
struct YamlValue {
  const std::string* scalar = nullptr;
  bool quoted = false;
  std::string name, where;
};

// Each throws lt::InputError at v.where naming v.name: "NAME must be a finite
// number", "... must be an integer in [LO, HI]", "... must be a string", with
// ", got 'TEXT'" when the value is a scalar.
double YamlNumber(const YamlValue& v);
long long YamlInteger(const YamlValue& v, long long lo, long long hi);
std::string YamlString(const YamlValue& v);

// Whether the whole of `s` is a finite number (strtod's forms), into *v.
bool ParseYamlReal(const std::string& s, double* v);

}  // namespace lt

// The scalars of the YAML tree (pipeline/yaml_tree.h): comments, quoted
// scalars and the text of block scalars, as one line of YAML holds them.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace lt {

// Whether s[i] opens a quoted scalar: a quote where a value or key can start.
bool OpensYamlQuote(const std::string& s, size_t i);

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

}  // namespace lt

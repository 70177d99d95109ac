// Reading numbers and fields from text files (pose lists, G-code, robot pose
// files). Strict: a number is the whole field, finite, in the C locale.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lt {

// Parses the whole of `text` as a decimal number ("1", "-0.5", "+2.", ".5",
// "1e-3"). Returns nullopt when anything else is there, or when the value is not
// finite ("nan", "inf", "1e999").
std::optional<double> ParseFiniteNumber(std::string_view text);

// `text` without leading and trailing blanks (spaces, tabs, CR, LF).
std::string_view TrimBlanks(std::string_view text);

// Splits `text` at every `separator` (fields trimmed of blanks).
std::vector<std::string_view> SplitFields(std::string_view text, char separator);
// Field k (0-based) of a row read as a finite number (ParseFiniteNumber); an
// lt::InputError naming `where` ("file:line") otherwise: "field K is not a
// finite number: 'TEXT'", K 1-based.
double FiniteField(const std::vector<std::string_view>& fields, size_t k, const std::string& where);
// Splits `text` at runs of blanks (no empty fields).
std::vector<std::string_view> SplitBlanks(std::string_view text);

// The first `shown` of `items` for a message, and how many more:
// "a, b, c and 4 more" (all of them when there are no more than `shown`); each item
// between `quote`s when given ("'a', 'b' and 4 more").
std::string ListFirst(const std::vector<std::string>& items, size_t shown, char quote = 0);

// `text` with its ASCII letters in lower case (file extensions, column and
// channel names, URI schemes, G-code names: none of them locale-dependent).
std::string Lower(std::string_view text);

// An image size for messages: "640x480".
std::string SizeText(int width, int height);

// The whole content of a text file. Throws lt::InputError naming `display_name`
// when it cannot be read.
std::string ReadTextFile(const std::filesystem::path& path, const std::string& display_name);

}  // namespace lt

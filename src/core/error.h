// Errors that reach the user. InputError is bad input (a file, an option): the
// command prints it and exits with code 2. Anything else is an internal failure.
#pragma once

#include <stdexcept>
#include <string>

namespace lt {

// A problem with user input. `where` names the file and the place in it, for
// example "scene.json: /sensor/camera/f_number" or "part.gcode:120".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& where, const std::string& message)
      : std::runtime_error(where.empty() ? message : where + ": " + message),
        where_(where),
        message_(message) {}

  const std::string& where() const { return where_; }
  const std::string& message() const { return message_; }

 private:
  std::string where_;
  std::string message_;
};

// Formats a double the way error messages show values: shortest form that
// round-trips ("0", "0.1", "1e-09", "nan").
std::string FormatNumber(double v);

}  // namespace lt

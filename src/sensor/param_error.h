// Invalid sensor parameters. The Check() of each parameter struct and the
// constructors that validate physics (a distortion that folds inside the image)
// throw ParamError naming the offending key relative to the struct's JSON object
// ("f_number", "distortion", "sheet_power/2"). The parsers turn it into an
// lt::InputError with the full JSON pointer.
#pragma once

#include <stdexcept>
#include <string>

#include "core/json_reader.h"

namespace lt {

class ParamError : public std::invalid_argument {
 public:
  ParamError(std::string key, const std::string& message)
      : std::invalid_argument(key.empty() ? message : key + ": " + message), key_(std::move(key)), message_(message) {}
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }

 private:
  std::string key_;
  std::string message_;
};

// Rethrows e as an InputError at `object`'s pointer joined with e.key().
[[noreturn]] void ThrowAt(const json::Object& object, const ParamError& e);

// Runs f (which builds or checks parameters of the object) and turns a
// ParamError into an InputError pointing into `object`.
template <typename F>
auto WithPointer(const json::Object& object, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const ParamError& e) {
    ThrowAt(object, e);
  }
}

}  // namespace lt

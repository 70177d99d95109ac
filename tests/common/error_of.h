// ErrorOf: the lt::InputError message a piece of code throws, for tests of error
// messages in every module (tests/common is on each test program's include path).
#pragma once

#include <string>

#include "core/error.h"

namespace lt::test {

// Runs f and returns the InputError message it throws ("" when none).
template <typename F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace lt::test

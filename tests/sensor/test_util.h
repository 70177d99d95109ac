// Helpers shared by the sensor tests.
#pragma once

#include <string>

#include "core/error.h"
#include "core/json_reader.h"

namespace lt::test {

inline json::Document Doc(const std::string& text) { return json::Document::Parse(text, "scene.json", "/base"); }

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

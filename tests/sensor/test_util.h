// Helpers shared by the sensor tests.
#pragma once

#include <string>

#include "core/error.h"
#include "core/json_reader.h"
#include "error_of.h"

namespace lt::test {

inline json::Document Doc(const std::string& text) { return json::Document::Parse(text, "scene.json", "/base"); }

}  // namespace lt::test

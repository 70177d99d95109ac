// What every Value of a parsed JSON document shares: the document, its file's name and
// the folder its relative paths resolve against. Internal to json_reader.cpp (Value,
// Object) and json_document.cpp (Document).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace lt::json {

struct Context {
  nlohmann::json root;
  std::string file;
  std::filesystem::path base_dir;
};

}  // namespace lt::json

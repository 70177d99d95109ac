// Subcommands of `lasertwin`. Each cmd_*.cpp file registers itself with
// LT_REGISTER_COMMAND; main.cpp adds them all to the CLI11 app in name order.
//
// Exit codes: 0 success; 2 bad input (an lt::InputError or a usage error, message
// on stderr); 1 internal failure.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

#include "core/error.h"
#include "pipeline/extraction_options.h"

namespace lt::cli {

// Adds one subcommand (with its options and callback) to the app.
using AddCommand = std::function<void(CLI::App& app)>;

struct CommandRegistrar {
  CommandRegistrar(const std::string& name, AddCommand add);
};

// A number option that must be finite. CLI11 reads "nan" and "inf" into a
// double, and where NaN stands for "automatic" (--threshold, --high-threshold)
// a typed nan would silently become the default.
inline CLI::Validator FiniteNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        if (CLI::detail::lexical_cast(text, v) && std::isfinite(v)) return {};
        return "expected a finite number, got '" + text + "'";
      },
      "");
}

// --threshold: a finite number or "auto", blanks around it allowed: what
// ParseThreshold (which reads it after) accepts, by asking it.
inline CLI::Validator ThresholdValue() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double threshold = 0;
        ThresholdMode mode = ThresholdMode::kFixed;
        try {
          ParseThreshold(text, "--threshold", &threshold, &mode);
        } catch (const InputError&) {
          return "expected a finite number or 'auto', got '" + text + "'";
        }
        return {};
      },
      "");
}

// An output file's folder must exist before any work: lt::InputError naming
// `option` otherwise.
inline void RequireOutputFolder(const std::string& option, const std::string& file) {
  std::error_code ec;
  const std::filesystem::path parent = std::filesystem::path(file).parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec)) {
    throw InputError(option, "the folder of " + file + " does not exist (" + parent.string() + ")");
  }
}

}  // namespace lt::cli

#define LT_CONCAT_INNER(a, b) a##b
#define LT_CONCAT(a, b) LT_CONCAT_INNER(a, b)
#define LT_REGISTER_COMMAND(name, add_fn) \
  static ::lt::cli::CommandRegistrar LT_CONCAT(lt_command_registrar_, __LINE__)(name, add_fn)

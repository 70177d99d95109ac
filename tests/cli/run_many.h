// Several independent `lasertwin` invocations at once (cli_util.h's RunCli),
// and a fresh temporary folder per test. Bad-input tables run their cases this
// way: each invocation mostly waits on process start-up.
#pragma once

#include <filesystem>
#include <future>
#include <string>
#include <vector>

#include "cli_util.h"

namespace lt::test {

// Runs up to 4 invocations at a time; results in the order of `args`.
inline std::vector<CliResult> RunMany(const std::vector<std::string>& args) {
  std::vector<std::future<CliResult>> runs;
  for (const auto& a : args) {
    if (runs.size() >= 4) runs[runs.size() - 4].wait();
    runs.push_back(std::async(std::launch::async, [a] { return RunCli(a); }));
  }
  std::vector<CliResult> out;
  for (auto& r : runs) out.push_back(r.get());
  return out;
}

// TestFolder(name), created.
inline std::filesystem::path NewTestFolder(const std::string& name) {
  std::filesystem::path dir = TestFolder(name);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace lt::test

// Running build/bin/lasertwin from command-line tests: exit code, stdout and
// stderr of one invocation, and a fresh temporary folder per test.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <vector>
#include <sstream>
#include <string>

namespace lt::clitest {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string out, err;
};

inline std::string ReadAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string Quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// A new empty folder under the system's temporary folder.
inline fs::path TempDir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("lt_cli_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Runs `lasertwin ARGS` (ARGS is passed to the shell) with stdout and stderr captured.
inline Result RunLasertwin(const std::string& args) {
  static std::atomic<int> counter{0};
  const fs::path tmp =
      fs::temp_directory_path() / ("lt_cli_run_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string command =
      std::string(LT_LASERTWIN) + " " + args + " >" + Quoted(tmp.string() + ".out") + " 2>" + Quoted(tmp.string() + ".err");
  const int status = std::system(command.c_str());
  Result r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadAll(tmp.string() + ".out");
  r.err = ReadAll(tmp.string() + ".err");
  fs::remove(tmp.string() + ".out");
  fs::remove(tmp.string() + ".err");
  return r;
}

// Runs several independent invocations, up to 4 at a time; results in order.
inline std::vector<Result> RunMany(const std::vector<std::string>& args) {
  std::vector<std::future<Result>> runs;
  for (const auto& a : args) {
    if (runs.size() >= 4) runs[runs.size() - 4].wait();
    runs.push_back(std::async(std::launch::async, [a] { return RunLasertwin(a); }));
  }
  std::vector<Result> out;
  for (auto& r : runs) out.push_back(r.get());
  return out;
}

}  // namespace lt::clitest

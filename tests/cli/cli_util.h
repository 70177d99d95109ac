// Running build/bin/lasertwin from tests, with stdout, stderr and exit code.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace lt::test {

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

inline std::string ReadFile(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs `lasertwin ARGS` (ARGS is shell-quoted by the caller) with outputs captured.
inline CliResult RunCli(const std::string& args) {
  static std::atomic<int> counter{0};
  const auto tmp = std::filesystem::temp_directory_path() /
                   ("lt_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string command = std::string(LT_LASERTWIN) + " " + args + " >" + tmp.string() + ".out 2>" +
                              tmp.string() + ".err";
  int status = std::system(command.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadFile(tmp.string() + ".out");
  r.err = ReadFile(tmp.string() + ".err");
  std::filesystem::remove(tmp.string() + ".out");
  std::filesystem::remove(tmp.string() + ".err");
  return r;
}

// Built by appending: GCC 12 warns falsely (-Wrestrict) on "'" + std::string where inlined.
inline std::string Quoted(const std::filesystem::path& p) {
  std::string q = "'";
  q += p.string();
  q += "'";
  return q;
}

// A fresh, empty temporary folder named after the running test.
inline std::filesystem::path TestFolder(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("lt_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace lt::test

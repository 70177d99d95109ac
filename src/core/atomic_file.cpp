#include "core/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>

namespace lt {

void WriteAtomically(const std::filesystem::path& path,
                     const std::function<void(const std::filesystem::path&)>& write) {
  std::filesystem::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  try {
    write(tmp);
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

void WriteFileAtomically(const std::filesystem::path& path, const std::string& contents) {
  WriteAtomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot create " + tmp.string());
    out.write(contents.data(), std::streamsize(contents.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  });
}

}  // namespace lt

#include "core/atomic_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

namespace lt {
namespace {

std::filesystem::path TempDir() {
  auto dir = std::filesystem::temp_directory_path() /
             ("lt_atomic_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
              ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(AtomicFile, WritesAndReplaces) {
  auto dir = TempDir();
  auto path = dir / "a.txt";
  WriteFileAtomically(path, "one");
  WriteFileAtomically(path, "two");
  std::ifstream in(path);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "two");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  std::filesystem::remove_all(dir);
}

TEST(AtomicFile, FailedWriteLeavesOldFileAndNoTemporary) {
  auto dir = TempDir();
  auto path = dir / "a.txt";
  WriteFileAtomically(path, "old");
  EXPECT_THROW(WriteAtomically(path,
                               [](const std::filesystem::path& tmp) {
                                 std::ofstream(tmp) << "half";
                                 throw std::runtime_error("interrupted");
                               }),
               std::runtime_error);
  std::ifstream in(path);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "old");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lt

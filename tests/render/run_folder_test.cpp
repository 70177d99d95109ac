#include "render/run_folder.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"

namespace lt {
namespace {

class RunFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (std::string("lt_run_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
  nlohmann::json scene_ = {{"seed", 3}};
};

TEST_F(RunFolderTest, RefusesExistingRunWithoutResume) {
  { RunFolder run(dir_, scene_, false); }
  EXPECT_THROW(RunFolder(dir_, scene_, false), InputError);
  EXPECT_NO_THROW(RunFolder(dir_, scene_, true));
}

TEST_F(RunFolderTest, ResumeNeedsTheSameScene) {
  { RunFolder run(dir_, scene_, false); }
  EXPECT_THROW(RunFolder(dir_, nlohmann::json{{"seed", 4}}, true), InputError);
}

TEST_F(RunFolderTest, ManifestKeepsCompletedFramesSorted) {
  {
    RunFolder run(dir_, scene_, false);
    run.CompleteFrame(2, {{"index", 2}});
    run.CompleteFrame(0, {{"index", 0}});
  }
  RunFolder again(dir_, scene_, true);
  EXPECT_TRUE(again.IsComplete(0));
  EXPECT_FALSE(again.IsComplete(1));
  EXPECT_TRUE(again.IsComplete(2));
  std::ifstream in(dir_ / "manifest.jsonl");
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, R"({"index":0})");
}

TEST_F(RunFolderTest, CorruptManifestNamesTheLine) {
  { RunFolder run(dir_, scene_, false); }
  std::ofstream(dir_ / "manifest.jsonl") << "{\"index\":0}\n{\"index\": 1\n";
  try {
    RunFolder::ReadManifest(dir_);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("manifest.jsonl:2"), std::string::npos) << e.what();
  }
}

TEST(FrameNames, ArePadded) {
  EXPECT_EQ(RunFolder::FrameImageName(12), "frames/000012.png");
  EXPECT_EQ(RunFolder::CentersName(3), "gt/000003_centers.csv");
}

}  // namespace
}  // namespace lt

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "pipeline/stripe_csv.h"

namespace lt {
namespace {

std::filesystem::path TempFile(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / "lt_stripe_csv_test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

TEST(StripeCsv, HeaderAndRoundTrip) {
  std::vector<StripePoint> pts = {{12.34567, 3, 4.5, 200, 2}, {0.5, 4, 1.25, 17.5, -1}};
  EXPECT_EQ(FormatStripeCsv(pts, false).substr(0, 19), "u,v,width,strength\n");
  EXPECT_EQ(FormatStripeCsv(pts, true).substr(0, 25), "u,v,width,strength,plane\n");
  auto path = TempFile("points.csv");
  WriteStripeCsv(path, pts, true);
  bool with_plane = false;
  auto back = ReadStripeCsv(path, &with_plane);
  EXPECT_TRUE(with_plane);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_NEAR(back[0].u, 12.34567, 5e-5);  // 4 decimals
  EXPECT_EQ(back[0].v, 3);
  EXPECT_EQ(back[0].plane, 2);
  EXPECT_EQ(back[1].plane, -1);
  WriteStripeCsv(path, pts, false);
  back = ReadStripeCsv(path, &with_plane);
  EXPECT_FALSE(with_plane);
  EXPECT_EQ(back[0].plane, -1);
}

TEST(StripeCsv, BadFilesNameTheLine) {
  auto path = TempFile("bad.csv");
  auto expect_error = [&](const std::string& text, const std::string& where) {
    std::ofstream(path) << text;
    try {
      ReadStripeCsv(path);
      ADD_FAILURE() << "expected InputError for " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where(), path.string() + where) << e.what();
    }
  };
  expect_error("", ":1");
  expect_error("x,y\n", ":1");
  expect_error("u,v,width,strength\n1,2,3,4\n1,2,3\n", ":3");
  expect_error("u,v,width,strength\n1,2,nan,4\n", ":2");
  expect_error("u,v,width,strength,plane\n1,2,3,4,x\n", ":2");
  EXPECT_THROW(ReadStripeCsv(TempFile("missing.csv")), InputError);
}

}  // namespace
}  // namespace lt

#include "core/image_io.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"

namespace lt {
namespace {

class ImageIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (std::string("lt_image_io_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

template <typename T>
Image<T> Ramp(int w, int h, int c, T scale) {
  Image<T> img(w, h, c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) img.At(x, y, k) = T((x + 3 * y + 7 * k) % 200) * scale;
  return img;
}

TEST_F(ImageIo, Png8RoundTripKeepsType) {
  auto img = Ramp<uint8_t>(17, 5, 1, 1);
  WriteImage(dir_ / "a.png", img);
  AnyImage back = ReadImage(dir_ / "a.png");
  ASSERT_TRUE(std::holds_alternative<Image<uint8_t>>(back));
  EXPECT_EQ(std::get<Image<uint8_t>>(back).pixels, img.pixels);
}

TEST_F(ImageIo, Png16RoundTripKeepsType) {
  auto img = Ramp<uint16_t>(9, 4, 3, 300);
  WriteImage(dir_ / "a.png", img);
  AnyImage back = ReadImage(dir_ / "a.png");
  ASSERT_TRUE(std::holds_alternative<Image<uint16_t>>(back));
  EXPECT_EQ(std::get<Image<uint16_t>>(back).pixels, img.pixels);
  Image<float> f = ReadImageFloat(dir_ / "a.png");
  EXPECT_EQ(f.At(2, 3, 1), float(img.At(2, 3, 1)));  // no rescaling
}

TEST_F(ImageIo, ExrFloatRoundTripWithChannelNames) {
  Image<float> img(6, 3, 2);
  for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = 0.1f * float(i) - 1.0f;
  WriteImage(dir_ / "a.exr", img, true, {"Z", "id"});
  AnyImage back = ReadImage(dir_ / "a.exr");
  ASSERT_TRUE(std::holds_alternative<Image<float>>(back));
  EXPECT_EQ(std::get<Image<float>>(back).pixels, img.pixels);
}

TEST_F(ImageIo, MissingTruncatedAndEmptyFilesAreInputErrors) {
  EXPECT_THROW(ReadImage(dir_ / "none.png"), InputError);
  auto img = Ramp<uint8_t>(64, 64, 1, 1);
  WriteImage(dir_ / "a.png", img);
  auto size = std::filesystem::file_size(dir_ / "a.png");
  std::filesystem::resize_file(dir_ / "a.png", size / 2);
  EXPECT_THROW(ReadImage(dir_ / "a.png"), InputError);
  std::ofstream(dir_ / "empty.png").close();
  EXPECT_THROW(ReadImage(dir_ / "empty.png"), InputError);
  EXPECT_THROW(ReadImage(dir_), InputError);
}

TEST_F(ImageIo, ErrorNamesTheFile) {
  try {
    ReadImage(dir_ / "none.png");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none.png"), std::string::npos);
  }
}

TEST_F(ImageIo, ViewCropStaysInside) {
  auto img = Ramp<uint8_t>(10, 8, 2, 1);
  auto v = img.View().Crop(2, 3, 4, 2);
  EXPECT_EQ(v.At(0, 0, 1), img.At(2, 3, 1));
  EXPECT_EQ(v.At(3, 1, 0), img.At(5, 4, 0));
  EXPECT_THROW(img.View().Crop(8, 0, 3, 1), std::out_of_range);
}

}  // namespace
}  // namespace lt

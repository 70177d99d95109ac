#include "core/image_io.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

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

// A rendered frame's EXR files depend only on the pixels: OpenEXR's capture
// date (OpenImageIO's DateTime, the time of writing unless set) is left empty,
// so the same frame rendered twice gives the same bytes.
TEST_F(ImageIo, ExrCarriesNoTimeOfWriting) {
  Image<float> img(4, 2, 1, 0.5f);
  WriteImage(dir_ / "a.exr", img, true, {"Z"});
  auto in = OIIO::ImageInput::open((dir_ / "a.exr").string());
  ASSERT_TRUE(in);
  const std::string date = in->spec().get_string_attribute("DateTime", "absent");
  EXPECT_TRUE(date == "absent" || date.empty()) << date;
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

// Writes `values` (w x h x c) to `path` through OpenImageIO as `type`.
template <typename T>
void WriteRaw(const std::filesystem::path& path, int w, int h, int c, OIIO::TypeDesc type,
              const std::vector<T>& values) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(w, h, c, type);
  if (c == 4) spec.alpha_channel = 3;
  ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(type, values.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// OpenImageIO 2.4 reads a truncated TIFF "successfully" with the missing rows
// zero and only an error message left behind: that must be an InputError.
TEST_F(ImageIo, TruncatedTiffIsAnInputErrorNamingTheFile) {
  auto img = Ramp<uint8_t>(100, 80, 1, 1);
  for (auto& v : img.pixels) v = uint8_t(v | 1);  // no zero pixels
  WriteImage(dir_ / "a.tif", img);
  AnyImage whole = ReadImage(dir_ / "a.tif");
  EXPECT_EQ(std::get<Image<uint8_t>>(whole).pixels, img.pixels);
  std::filesystem::resize_file(dir_ / "a.tif", std::filesystem::file_size(dir_ / "a.tif") * 6 / 10);
  try {
    ReadImage(dir_ / "a.tif");
    FAIL() << "a truncated TIFF was read without an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.tif"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot decode image"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadImageFloat(dir_ / "a.tif"), InputError);
}

// PNG stores straight alpha; OpenImageIO's default multiplies it into the colour.
TEST_F(ImageIo, AlphaIsNotMultipliedIntoTheColour) {
  Image<uint8_t> rgba(4, 3, 4);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      rgba.At(x, y, 0) = 200;
      rgba.At(x, y, 1) = 100;
      rgba.At(x, y, 2) = 10;
      rgba.At(x, y, 3) = 128;
    }
  WriteImage(dir_ / "a.png", rgba);
  AnyImage back = ReadImage(dir_ / "a.png");
  ASSERT_TRUE(std::holds_alternative<Image<uint8_t>>(back));
  EXPECT_EQ(std::get<Image<uint8_t>>(back).pixels, rgba.pixels);
  Image<float> f = ReadImageFloat(dir_ / "a.png");
  EXPECT_EQ(f.At(1, 2, 0), 200.0f);
  EXPECT_EQ(f.At(1, 2, 3), 128.0f);
}

// A camera frame saved with alpha (grey+alpha, RGBA) is a mono or RGB frame:
// AlphaChannel::kDrop leaves the alpha channel out and keeps the others as stored.
TEST_F(ImageIo, AlphaCanBeLeftOut) {
  Image<uint16_t> rgba(5, 3, 4);
  Image<uint16_t> ga(5, 3, 2);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      for (int c = 0; c < 3; ++c) rgba.At(x, y, c) = uint16_t(1000 * c + 100 * y + x);
      rgba.At(x, y, 3) = 65535;
      ga.At(x, y, 0) = uint16_t(40000 + 10 * x + y);
      ga.At(x, y, 1) = uint16_t(7 * x);  // any alpha, not only opaque
    }
  WriteImage(dir_ / "rgba.png", rgba);
  WriteImage(dir_ / "ga.png", ga);
  const AnyImage kept = ReadImage(dir_ / "rgba.png", AlphaChannel::kKeep);
  ASSERT_TRUE(std::holds_alternative<Image<uint16_t>>(kept));
  EXPECT_EQ(std::get<Image<uint16_t>>(kept).pixels, rgba.pixels);
  const AnyImage rgb = ReadImage(dir_ / "rgba.png", AlphaChannel::kDrop);
  ASSERT_TRUE(std::holds_alternative<Image<uint16_t>>(rgb));
  const Image<uint16_t>& c3 = std::get<Image<uint16_t>>(rgb);
  ASSERT_EQ(c3.channels, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(c3.At(x, y, c), rgba.At(x, y, c));
  const AnyImage grey = ReadImage(dir_ / "ga.png", AlphaChannel::kDrop);
  ASSERT_TRUE(std::holds_alternative<Image<uint16_t>>(grey));
  const Image<uint16_t>& c1 = std::get<Image<uint16_t>>(grey);
  ASSERT_EQ(c1.channels, 1);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) EXPECT_EQ(c1.At(x, y), ga.At(x, y, 0));
  // Without alpha nothing is dropped.
  Image<uint8_t> rgb8(4, 2, 3, 9);
  WriteImage(dir_ / "rgb.png", rgb8);
  EXPECT_EQ(std::get<Image<uint8_t>>(ReadImage(dir_ / "rgb.png", AlphaChannel::kDrop)).pixels, rgb8.pixels);
}

// Signed and 32-bit integers come back as float with their own values: no
// conversion through uint16 (doubled, negatives clamped) or to 0..1.
TEST_F(ImageIo, SignedAndWideIntegerTiffsKeepTheirRawValues) {
  const std::vector<int16_t> s16 = {-1234, 0, 7, 25699, -32768, 32767};
  WriteRaw(dir_ / "s16.tif", 3, 2, 1, OIIO::TypeDesc::INT16, s16);
  AnyImage a = ReadImage(dir_ / "s16.tif");
  ASSERT_TRUE(std::holds_alternative<Image<float>>(a));
  const auto& fa = std::get<Image<float>>(a);
  ASSERT_EQ(fa.pixels.size(), s16.size());
  for (size_t i = 0; i < s16.size(); ++i) EXPECT_EQ(fa.pixels[i], float(s16[i])) << i;

  const std::vector<uint32_t> u32 = {0, 1, 51399, 70000, 1u << 24, 4000000000u};
  WriteRaw(dir_ / "u32.tif", 2, 3, 1, OIIO::TypeDesc::UINT32, u32);
  AnyImage b = ReadImage(dir_ / "u32.tif");
  ASSERT_TRUE(std::holds_alternative<Image<float>>(b));
  const auto& fb = std::get<Image<float>>(b);
  ASSERT_EQ(fb.pixels.size(), u32.size());
  for (size_t i = 0; i < u32.size(); ++i) EXPECT_EQ(fb.pixels[i], float(u32[i])) << i;
  // The overload that also returns channel names reads the same values.
  std::vector<std::string> names;
  EXPECT_EQ(ReadImageFloat(dir_ / "u32.tif", &names).pixels, fb.pixels);
  EXPECT_EQ(ReadImageFloat(dir_ / "s16.tif", &names).pixels, fa.pixels);
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

// What image files from real cameras declare beyond their sample type
// (ImageFileFacts: sBIT, colour tags, Orientation), files of several frames
// and empty files (docs/extraction.md, "Image files from real cameras").
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <fstream>

#include "core/error.h"
#include "core/image_io.h"
#include "error_of.h"
#include "png_chunk_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::InsertPngChunk;

class ImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (std::string("lt_image_files_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

// A 16-bit image of `channels` channels whose first channel ramps up to `largest`
// (the others full: an opaque alpha).
Image<uint16_t> Ramp16(int channels, int largest) {
  Image<uint16_t> img(16, 4, channels, 65535);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.At(x, y, 0) = uint16_t(largest * (x + 16 * y) / 63);
  return img;
}

// Writes `img` with OpenImageIO, with one extra attribute (an int).
void WriteWith(const std::filesystem::path& path, const Image<uint8_t>& img, const char* name, int value) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(img.width, img.height, img.channels, OIIO::TypeDesc::UINT8);
  spec.attribute(name, value);
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, img.pixels.data()));
  ASSERT_TRUE(out->close());
}

ImageFileFacts FactsOf(const std::filesystem::path& path) {
  ImageFileFacts facts;
  ReadImage(path, AlphaChannel::kDrop, &facts);
  return facts;
}

// OpenImageIO 2.4 calls every PNG without a gAMA chunk "sRGB"; a frame written
// here (linear, no colour chunk) must not look encoded.
TEST_F(ImageFiles, APngWithoutColourChunksDeclaresNothing) {
  WriteImage(dir_ / "a.png", Ramp16(1, 4000));
  const ImageFileFacts f = FactsOf(dir_ / "a.png");
  EXPECT_EQ(f.encoding, "");
  EXPECT_EQ(f.significant_bits, 0);
  EXPECT_EQ(f.unscaled_full_scale, 0);
  EXPECT_EQ(f.orientation, 1);
}

// sBIT 12 in a 16-bit PNG: values at most 4095 are the 12 bits stored unscaled
// (full scale 4095); values shifted to the top bits (the PNG standard's way)
// keep 65535. The values are read as stored either way.
TEST_F(ImageFiles, SbitChunkGivesTheFullScaleOfUnscaledBits) {
  const Image<uint16_t> lsb = Ramp16(1, 4095);
  WriteImage(dir_ / "lsb.png", lsb);
  InsertPngChunk(dir_ / "lsb.png", "sBIT", std::string(1, char(12)));
  ImageFileFacts f;
  AnyImage back = ReadImage(dir_ / "lsb.png", AlphaChannel::kDrop, &f);
  EXPECT_EQ(std::get<Image<uint16_t>>(back).pixels, lsb.pixels);
  EXPECT_EQ(f.significant_bits, 12);
  EXPECT_EQ(f.unscaled_full_scale, 4095);

  Image<uint16_t> msb = lsb;
  for (uint16_t& v : msb.pixels) v = uint16_t(v << 4);
  WriteImage(dir_ / "msb.png", msb);
  InsertPngChunk(dir_ / "msb.png", "sBIT", std::string(1, char(12)));
  f = FactsOf(dir_ / "msb.png");
  EXPECT_EQ(f.significant_bits, 12);
  EXPECT_EQ(f.unscaled_full_scale, 0);

  // A dim frame of shifted samples (12-bit peak 200: every sample at most 4095)
  // is still shifted: its low 4 bits are clear, by a shift or by repeating the
  // high bits (v << 4 | v >> 8). Before, it was read as 12 bits unscaled, and
  // one brighter pixel flipped the frame back.
  for (const bool repeat : {false, true}) {
    Image<uint16_t> dim = Ramp16(1, 200);
    for (uint16_t& v : dim.pixels) v = uint16_t(v << 4 | (repeat ? v >> 8 : 0));
    WriteImage(dir_ / "dim.png", dim);
    InsertPngChunk(dir_ / "dim.png", "sBIT", std::string(1, char(12)));
    f = FactsOf(dir_ / "dim.png");
    EXPECT_EQ(f.significant_bits, 12);
    EXPECT_EQ(f.unscaled_full_scale, 0) << repeat;
  }
}

// Grey+alpha: sBIT gives the grey's bits and the alpha's; an opaque alpha
// (65535) does not make the grey look scaled.
TEST_F(ImageFiles, SbitOfGreyAndAlphaLeavesTheAlphaOut) {
  WriteImage(dir_ / "ga.png", Ramp16(2, 1000));
  InsertPngChunk(dir_ / "ga.png", "sBIT", std::string{char(10), char(16)});
  const ImageFileFacts f = FactsOf(dir_ / "ga.png");
  EXPECT_EQ(f.significant_bits, 10);
  EXPECT_EQ(f.unscaled_full_scale, 1023);
}

TEST_F(ImageFiles, ColourChunksAndExifSayHowValuesEncodeLight) {
  const Image<uint8_t> img(8, 4, 1, 100);
  WriteImage(dir_ / "srgb.png", img);
  InsertPngChunk(dir_ / "srgb.png", "sRGB", std::string(1, char(0)));
  EXPECT_EQ(FactsOf(dir_ / "srgb.png").encoding, "an sRGB chunk");

  WriteImage(dir_ / "gamma.png", img);
  InsertPngChunk(dir_ / "gamma.png", "gAMA", test::BigEndian32(45455));
  ImageFileFacts f = FactsOf(dir_ / "gamma.png");
  EXPECT_EQ(f.encoding, "a gAMA chunk (gamma 2.2)");
  EXPECT_DOUBLE_EQ(f.gamma, 2.2);

  WriteImage(dir_ / "linear.png", img);  // gAMA 1.0: linear, nothing to say
  InsertPngChunk(dir_ / "linear.png", "gAMA", test::BigEndian32(100000));
  EXPECT_EQ(FactsOf(dir_ / "linear.png").encoding, "");

  WriteWith(dir_ / "exif.jpg", img, "Exif:ColorSpace", 1);
  EXPECT_EQ(FactsOf(dir_ / "exif.jpg").encoding, "EXIF ColorSpace sRGB");
  WriteImage(dir_ / "plain.jpg", img);
  EXPECT_EQ(FactsOf(dir_ / "plain.jpg").encoding, "");
}

// The Orientation tag is reported, never applied: the pixels stay as stored.
TEST_F(ImageFiles, OrientationIsReportedNotApplied) {
  Image<uint8_t> img(6, 3, 1, 0);
  img.At(5, 0) = 200;
  WriteWith(dir_ / "o6.tif", img, "Orientation", 6);
  ImageFileFacts f;
  AnyImage back = ReadImage(dir_ / "o6.tif", AlphaChannel::kDrop, &f);
  EXPECT_EQ(f.orientation, 6);
  const auto& b = std::get<Image<uint8_t>>(back);
  EXPECT_EQ(b.width, 6);
  EXPECT_EQ(b.pixels, img.pixels);
}

// Writes a TIFF of one page per image.
void WritePages(const std::filesystem::path& path, const std::vector<Image<uint8_t>>& pages) {
  std::vector<OIIO::ImageSpec> specs;
  for (const auto& p : pages) specs.emplace_back(p.width, p.height, p.channels, OIIO::TypeDesc::UINT8);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path.string(), int(specs.size()), specs.data()));
  for (size_t i = 0; i < pages.size(); ++i) {
    if (i > 0) {
      ASSERT_TRUE(out->open(path.string(), specs[i], OIIO::ImageOutput::AppendSubimage));
    }
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pages[i].pixels.data()));
  }
  ASSERT_TRUE(out->close());
}

// A stack of frames in one TIFF was read as its first page, the others dropped
// unseen; it is an error naming the file and the count. A smaller second page
// (a thumbnail) is no frame.
TEST_F(ImageFiles, SeveralFramesInOneFileAreAnError) {
  const Image<uint8_t> frame(8, 6, 1, 50), thumb(4, 3, 1, 50);
  WritePages(dir_ / "stack.tif", {frame, frame, frame});
  const std::string e = ErrorOf([&] { ReadImage(dir_ / "stack.tif"); });
  EXPECT_NE(e.find("stack.tif: holds 3 images of 8x6"), std::string::npos) << e;
  EXPECT_NE(ErrorOf([&] { ReadImageFileSize(dir_ / "stack.tif"); }), "");

  WritePages(dir_ / "thumb.tif", {frame, thumb});
  EXPECT_EQ(std::get<Image<uint8_t>>(ReadImage(dir_ / "thumb.tif")).pixels, frame.pixels);
}

TEST_F(ImageFiles, AnEmptyFileIsNamedAsEmpty) {
  std::ofstream(dir_ / "zero.png").close();
  const std::string e = ErrorOf([&] { ReadImage(dir_ / "zero.png"); });
  EXPECT_NE(e.find("zero.png: is empty (0 bytes)"), std::string::npos) << e;
}

TEST_F(ImageFiles, FileSizeNamesTheSampleType) {
  WriteImage(dir_ / "a.png", Image<uint8_t>(4, 2, 1, 0));
  WriteImage(dir_ / "b.png", Image<uint16_t>(4, 2, 1, 0));
  WriteImage(dir_ / "c.exr", Image<float>(4, 2, 1, 0.f));
  EXPECT_EQ(ReadImageFileSize(dir_ / "a.png").sample_type, "8-bit");
  EXPECT_EQ(ReadImageFileSize(dir_ / "b.png").sample_type, "16-bit");
  EXPECT_EQ(ReadImageFileSize(dir_ / "c.exr").sample_type, "float");
}

// A header's size was believed: a 69-byte PNG declaring 60000x60000 RGBA at 16
// bits made extract say "internal error: std::bad_alloc" (28.8 GB asked for; one
// of 30000x30000 had 7.2 GB allocated and zeroed before the decoder failed on
// its first row), and so did a 42-byte PGM declaring 51000000x2 (OpenImageIO
// reads 256 rows at a time: 13 GB). Each is an error naming the file and the
// size (found reading the image reader for tools/fuzz/fuzz_image, the PGM by it).
TEST_F(ImageFiles, AHeaderDeclaringAnImpossibleSizeIsAnError) {
  using test::BigEndian32;
  using test::Chunk;
  const std::string ihdr = BigEndian32(1000000) + BigEndian32(1000000) + std::string{16, 6, 0, 0, 0};
  std::ofstream(dir_ / "huge.png", std::ios::binary)
      << std::string("\x89PNG\r\n\x1a\n", 8) + Chunk("IHDR", ihdr) + Chunk("IDAT", std::string(12, '\0')) +
             Chunk("IEND", "");
  const std::string e = ErrorOf([&] { ReadImage(dir_ / "huge.png", AlphaChannel::kDrop); });
  EXPECT_NE(e.find("huge.png: its header declares 1000000x1000000 pixels of 4 channels (8000.0 GB to read); "
                   "images above 4 GB are not read"),
            std::string::npos)
      << e;
  EXPECT_NE(ErrorOf([&] { ReadImageFileSize(dir_ / "huge.png"); }).find("its header declares"), std::string::npos);

  std::ofstream(dir_ / "wide.pgm", std::ios::binary) << "P2\n51000000 2\n3\n0 1 2 3\n";
  const std::string w = ErrorOf([&] { ReadImage(dir_ / "wide.pgm", AlphaChannel::kDrop); });
  EXPECT_NE(w.find("wide.pgm: its header declares 51000000x2 pixels of 1 channel (13.1 GB to read, 256 rows at a "
                   "time); images above 4 GB are not read"),
            std::string::npos)
      << w;
}

}  // namespace
}  // namespace lt

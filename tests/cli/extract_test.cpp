// `lasertwin extract` end to end on bad input: missing, empty, corrupt,
// truncated and zero-size images, a folder, wrong channel choices, an ROI
// outside the image, NaN in a float image and an unknown method. Each gives
// exit code 2, nothing on stdout and an error naming the file (or option).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "core/image.h"
#include "core/image_io.h"
#include "core/random.h"
#include "png_chunk_util.h"
#include "run_many.h"

namespace lt::test {
namespace {

namespace fs = std::filesystem;

using ::testing::HasSubstr;
using ::testing::Not;

void WriteBytes(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// An 8-bit grey PNG whose header says width x height (0 is invalid, but a file can say so).
std::string PngWithHeader(uint32_t width, uint32_t height) {
  std::string ihdr = {char(width >> 24), char(width >> 16), char(width >> 8), char(width),
                      char(height >> 24), char(height >> 16), char(height >> 8), char(height),
                      8, 0, 0, 0, 0};
  return std::string("\x89PNG\r\n\x1a\n", 8) + Chunk("IHDR", ihdr) + Chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) +
         Chunk("IEND", "");
}

// A mono 8-bit frame with a vertical stripe at column 20.
Image<uint8_t> StripeImage() {
  Image<uint8_t> img(64, 48, 1, 0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.At(x, y) = uint8_t(200 * std::exp(-0.5 * (x - 20) * (x - 20) / 4.0));
  return img;
}

class ExtractCommand : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = NewTestFolder("extract_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())); }

  // Queues `extract ARGS`, expected to fail on bad input with `message`.
  void ExpectInputError(const std::string& args, const std::string& message) { cases_.push_back({args, message}); }

  // Runs the queued cases (in parallel) and checks the common part of every
  // bad-input outcome: exit code 2, nothing on stdout, the message on stderr.
  void TearDown() override {
    std::vector<std::string> args;
    for (const auto& c : cases_) args.push_back("extract " + c.first);
    std::vector<CliResult> results = RunMany(args);
    for (size_t i = 0; i < cases_.size(); ++i) {
      const CliResult& r = results[i];
      EXPECT_EQ(r.exit_code, 2) << args[i] << "\n" << r.err;
      EXPECT_EQ(r.out, "") << args[i];
      EXPECT_THAT(r.err, HasSubstr("lasertwin: error: " + cases_[i].second)) << args[i];
    }
  }

  fs::path dir_;
  std::vector<std::pair<std::string, std::string>> cases_;
};

TEST_F(ExtractCommand, GoodImageWorks) {
  const fs::path p = dir_ / "stripe.png";
  WriteImage(p, StripeImage());
  CliResult r = RunCli("extract " + Quoted(p));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("u,v,width,strength\n20.0000,0.0000,"));
}

// max and com find one stripe per line: asked for several planes, the command
// says which methods see them all.
TEST_F(ExtractCommand, OneStripeMethodsWithSeveralPlanesWarn) {
  const fs::path p = dir_ / "stripe.png";
  WriteImage(p, StripeImage());
  CliResult r = RunCli("extract " + Quoted(p) + " --planes 2 --method max");
  EXPECT_THAT(r.err, HasSubstr("lasertwin: warning: max finds one stripe per search line, but --planes is 2: use "
                               "--method multicom or steger"));
  r = RunCli("extract " + Quoted(p) + " --planes 2 --method multicom");
  EXPECT_THAT(r.err, Not(HasSubstr("finds one stripe per search line")));
  // Without --method, several planes take multicom.
  r = RunCli("extract " + Quoted(p) + " --planes 2");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, Not(HasSubstr("finds one stripe per search line")));
}

// --background takes a level or `local` (a per-peak background line, for
// ambient light); anything else is an option error naming the choices.
TEST_F(ExtractCommand, BackgroundLocalOrLevel) {
  const fs::path p = dir_ / "stripe.png";
  Image<uint8_t> img = StripeImage();
  for (int y = 0; y < img.height; ++y)  // ambient ramp of 1 DN/px under the stripe
    for (int x = 0; x < img.width; ++x) img.At(x, y) = uint8_t(std::min(255, img.At(x, y) + x));
  WriteImage(p, img);
  CliResult r = RunCli("extract " + Quoted(p) + " --background local --method multicom");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("u,v,width,strength\n20.0"));
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1 + img.height) << r.out;
  ExpectInputError(Quoted(p) + " --background lokal", "--background: expected a level (a number) or 'local', got 'lokal'");
  ExpectInputError(Quoted(p) + " --background 5x", "--background: expected a level (a number) or 'local', got '5x'");
}

// --transfer srgb linearizes an sRGB-encoded frame (a webcam's, a JPEG's)
// before extraction: the width column is the light's FWHM again (the encoded
// profile is about 1.5 times wider); a bad value names the choices.
TEST_F(ExtractCommand, TransferLinearizesAnSrgbFrame) {
  Image<uint8_t> img(64, 48, 1, 0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double light = 0.8 * std::exp(-0.5 * (x - 20) * (x - 20) / 4.0);  // sigma 2: FWHM 4.71
      const double code = light <= 0.0031308 ? 12.92 * light : 1.055 * std::pow(light, 1 / 2.4) - 0.055;
      img.At(x, y) = uint8_t(std::lround(255 * code));
    }
  const fs::path p = dir_ / "srgb.png";
  WriteImage(p, img);
  auto first_width = [&](const std::string& options) {
    const CliResult r = RunCli("extract " + Quoted(p) + options);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    double u = 0, v = 0, width = 0;
    EXPECT_EQ(std::sscanf(r.out.c_str(), "u,v,width,strength\n%lf,%lf,%lf", &u, &v, &width), 3) << r.out;
    EXPECT_NEAR(u, 20, 1e-3);
    return width;
  };
  EXPECT_GT(first_width(""), 6.5);
  EXPECT_NEAR(first_width(" --transfer srgb"), 4.71, 0.1);
  EXPECT_NEAR(first_width(" --transfer gamma=2.2 --method steger"), 4.6, 0.3);
  ExpectInputError(Quoted(p) + " --transfer gamma=0.45",
                   "--transfer: expected linear, srgb or gamma=G with G in [1, 4] (e.g. gamma=2.2), got 'gamma=0.45'");
}

TEST_F(ExtractCommand, MissingEmptyCorruptAndTruncatedFiles) {
  const fs::path missing = dir_ / "missing.png";
  ExpectInputError(Quoted(missing), missing.string() + ": no such file");

  const fs::path empty = dir_ / "empty.png";
  WriteBytes(empty, "");
  ExpectInputError(Quoted(empty), empty.string() + ": is empty (0 bytes), not an image");

  const fs::path garbage = dir_ / "garbage.png";
  WriteBytes(garbage, std::string(200, 'x'));
  ExpectInputError(Quoted(garbage), garbage.string() + ": cannot read image");

  // Truncated inside the pixel data: the header reads, decoding fails. (EXR
  // and TIFF: libpng's error path leaks a string inside OpenImageIO 2.4, which
  // the sanitizer build would report, so a PNG is not used here.)
  Image<float> noise(64, 48, 1);
  Rng rng(7);
  for (float& v : noise.pixels) v = rng.NextFloat();
  for (const char* ext : {".exr", ".tif"}) {
    const fs::path full = dir_ / (std::string("noise") + ext);
    if (std::string(ext) == ".exr") {
      WriteImage(full, noise);
    } else {
      Image<uint16_t> n16(64, 48, 1);
      for (size_t i = 0; i < n16.pixels.size(); ++i) n16.pixels[i] = uint16_t(noise.pixels[i] * 65535);
      WriteImage(full, n16);
    }
    const std::string bytes = ReadFile(full);
    const fs::path truncated = dir_ / (std::string("truncated") + ext);
    WriteBytes(truncated, bytes.substr(0, bytes.size() * 4 / 5));
    ExpectInputError(Quoted(truncated), truncated.string() + ": cannot decode image");
  }

  const fs::path folder = dir_ / "folder.png";
  fs::create_directories(folder);
  ExpectInputError(Quoted(folder), folder.string() + ": is a folder, not an image");
}

TEST_F(ExtractCommand, ZeroSizeImages) {
  // PNG forbids a zero width or height; the decoder refuses such a header.
  const fs::path p = dir_ / "zero_width.png";
  WriteBytes(p, PngWithHeader(0, 10));
  ExpectInputError(Quoted(p), p.string() + ": cannot read image");
}

TEST_F(ExtractCommand, WrongChannelChoices) {
  Image<uint8_t> rgb(64, 48, 3, 0);
  for (int y = 0; y < 48; ++y) rgb.At(20, y, 0) = 200;
  const fs::path colour = dir_ / "colour.png";
  WriteImage(colour, rgb);
  ExpectInputError(Quoted(colour),
                   colour.string() + ": the image has 3 channels: choose the laser's channel (--channel, 0-based) or give channel weights (--weights, e.g. 1,0,0 for red)");
  ExpectInputError(Quoted(colour) + " --channel 3", colour.string() + ": channel 3 requested but the image has 3 channels");
  ExpectInputError(Quoted(colour) + " --weights 1,0", colour.string() + ": 2 channel weights given but the image has 3 channels");
  const fs::path mono = dir_ / "mono.png";
  WriteImage(mono, StripeImage());
  ExpectInputError(Quoted(mono) + " --weights 1,0,0", mono.string() + ": 3 channel weights given but the image has 1 channel");
  // The right choice works.
  CliResult r = RunCli("extract " + Quoted(colour) + " --channel 0");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// A frame saved with an alpha channel is extracted as the frame without it: a
// grey+alpha PNG as mono (no channel choice), an RGBA PNG as RGB (three weights).
TEST_F(ExtractCommand, AlphaChannelIsLeftOut) {
  const Image<uint8_t> mono = StripeImage();
  Image<uint8_t> ga(mono.width, mono.height, 2), rgba(mono.width, mono.height, 4);
  for (int y = 0; y < mono.height; ++y)
    for (int x = 0; x < mono.width; ++x) {
      ga.At(x, y, 0) = rgba.At(x, y, 0) = mono.At(x, y);
      rgba.At(x, y, 1) = uint8_t(mono.At(x, y) / 4);
      ga.At(x, y, 1) = rgba.At(x, y, 3) = 255;
    }
  WriteImage(dir_ / "mono.png", mono);
  WriteImage(dir_ / "ga.png", ga);
  WriteImage(dir_ / "rgba.png", rgba);
  const CliResult ref = RunCli("extract " + Quoted(dir_ / "mono.png"));
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  ASSERT_THAT(ref.out, HasSubstr("20.0000,0.0000,"));
  const CliResult g = RunCli("extract " + Quoted(dir_ / "ga.png"));
  EXPECT_EQ(g.exit_code, 0) << g.err;
  EXPECT_EQ(g.out, ref.out);
  const CliResult w = RunCli("extract " + Quoted(dir_ / "rgba.png") + " --weights 1,0,0");
  EXPECT_EQ(w.exit_code, 0) << w.err;
  EXPECT_EQ(w.out, ref.out);
  ExpectInputError(Quoted(dir_ / "rgba.png") + " --channel 3",
                   (dir_ / "rgba.png").string() + ": channel 3 requested but the image has 3 channels");
}

// A grey frame stored in colour channels (BMP, PPM, WebP and GIF hold no grey; many
// tools save monochrome frames as RGB) is grey: extracted from its one brightness
// without a channel choice. A GIF (ImageMagick 6.9's, 16x6, palette of 16 greys, a
// stripe at u = 7.3 in rows 0-4 and row 5 transparent) reads as RGB plus an alpha
// that OpenImageIO 2.4 names A but marks as channel 4 of 4; it is left out. Before,
// "the image has 3 channels" and "the image has 4 channels".
TEST_F(ExtractCommand, GreyStoredAsColourNeedsNoChannel) {
  const Image<uint8_t> mono = StripeImage();
  Image<uint8_t> rgb(mono.width, mono.height, 3);
  for (int y = 0; y < mono.height; ++y)
    for (int x = 0; x < mono.width; ++x)
      for (int c = 0; c < 3; ++c) rgb.At(x, y, c) = mono.At(x, y);
  WriteImage(dir_ / "mono.png", mono);
  WriteImage(dir_ / "grey_rgb.png", rgb);
  const CliResult ref = RunCli("extract " + Quoted(dir_ / "mono.png"));
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  const CliResult r = RunCli("extract " + Quoted(dir_ / "grey_rgb.png"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, ref.out);
  // One pixel's channels differing makes it colour.
  rgb.At(3, 4, 1) = uint8_t(rgb.At(3, 4, 1) + 1);
  WriteImage(dir_ / "tinted.png", rgb);
  ExpectInputError(Quoted(dir_ / "tinted.png"), (dir_ / "tinted.png").string() + ": the image has 3 channels: choose");

  const unsigned char gif[] = {
      0x47, 0x49, 0x46, 0x38, 0x39, 0x61, 0x10, 0x00, 0x06, 0x00, 0xf3, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x01, 0x01, 0x01, 0x03, 0x03, 0x03, 0x0a, 0x0a,
      0x0a, 0x14, 0x14, 0x14, 0x2d, 0x2d, 0x2d, 0x46, 0x46, 0x46, 0x78, 0x78,
      0x78, 0x9d, 0x9d, 0x9d, 0xcd, 0xcd, 0xcd, 0xe0, 0xe0, 0xe0, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x21, 0xf9, 0x04, 0x01, 0x00, 0x00, 0x0b, 0x00, 0x2c, 0x00, 0x00,
      0x00, 0x00, 0x10, 0x00, 0x06, 0x00, 0x00, 0x04, 0x20, 0x10, 0x48, 0x40,
      0x0c, 0x52, 0xe9, 0x94, 0x31, 0xbb, 0xa8, 0x57, 0xb6, 0x75, 0xd3, 0x67,
      0x61, 0xda, 0x20, 0x90, 0x80, 0x19, 0xa6, 0x6c, 0x0b, 0xa2, 0xe3, 0xb4,
      0xdc, 0x78, 0xae, 0x2f, 0x11, 0x00, 0x3b,
  };
  WriteBytes(dir_ / "stripe.gif", std::string(reinterpret_cast<const char*>(gif), sizeof(gif)));
  const CliResult g = RunCli("extract " + Quoted(dir_ / "stripe.gif") + " --min-width 0");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  std::istringstream lines(g.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "u,v,width,strength");
  int rows = 0;
  while (std::getline(lines, line)) {
    EXPECT_NEAR(std::stod(line), 7.3, 0.05) << line;  // 16 grey levels: 0.02 px of quantisation
    EXPECT_EQ(std::stoi(line.substr(line.find(',') + 1)), rows) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 5);  // the transparent row reads black
}

// A 12-bit camera's frame stored unscaled in a 16-bit PNG (values < 4096) is far
// below the default threshold (10% of 65535): the command says so, with the
// brightest value and the bits it fits in, and the suggested threshold finds the
// stripe. A dark 16-bit frame gets the brightest value without the bits.
TEST_F(ExtractCommand, TwelveBitFrameInASixteenBitFileIsNamedWhenBelowTheThreshold) {
  Image<uint16_t> img(64, 48, 1, 30);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      img.At(x, y) = uint16_t(std::lround(30 + 3970 * std::exp(-0.5 * (x - 20) * (x - 20) / 4.0)));
  const fs::path p = dir_ / "twelve.png";
  WriteImage(p, img);
  const CliResult r = RunCli("extract " + Quoted(p));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "u,v,width,strength\n");
  EXPECT_THAT(r.err, HasSubstr("note: " + p.string() + ": its brightest pixel is 4000, below the threshold 6553.5 (10% of 65535); "
                               "its values fit in 12 bits: for a 12-bit camera's frames stored unscaled give --threshold, e.g. "
                               "409.5 for 10% of 4095"));
  const CliResult t = RunCli("extract " + Quoted(p) + " --threshold 409.5");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_THAT(t.out, HasSubstr("\n20.0000,"));
  EXPECT_THAT(t.err, Not(HasSubstr("brightest")));
  const fs::path dark = dir_ / "dark.png";
  WriteImage(dark, Image<uint16_t>(64, 48, 1, 3));
  const CliResult d = RunCli("extract " + Quoted(dark));
  EXPECT_THAT(d.err, HasSubstr(dark.string() + ": its brightest pixel is 3, below the threshold 6553.5 (10% of 65535)\n"));
}

// The same 12-bit frame saying so by an sBIT chunk (as cameras' tools write
// it) is extracted with 10% of 4095 by default, with a note once; an sRGB
// chunk is warned about unless --transfer is given; a 2-page TIFF is refused.
// (Before: no point and the note above; no warning; the first page read alone.)
TEST_F(ExtractCommand, WhatTheFileDeclaresIsFollowedOrNamed) {
  Image<uint16_t> img(64, 48, 1, 30);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      img.At(x, y) = uint16_t(std::lround(30 + 3970 * std::exp(-0.5 * (x - 20) * (x - 20) / 4.0)));
  const fs::path p = dir_ / "twelve.png";
  WriteImage(p, img);
  InsertPngChunk(p, "sBIT", std::string(1, char(12)));
  const CliResult r = RunCli("extract " + Quoted(p));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("\n20.0000,"));
  EXPECT_THAT(r.err, HasSubstr("note: " + p.string() + ": its sBIT chunk declares 12 significant bits, stored unscaled "
                               "(no sample above 4095): the default threshold is 10% of 4095"));

  const fs::path srgb = dir_ / "srgb.png";
  WriteImage(srgb, StripeImage());
  InsertPngChunk(srgb, "sRGB", std::string(1, char(0)));
  EXPECT_THAT(RunCli("extract " + Quoted(srgb)).err,
              HasSubstr("warning: " + srgb.string() + ": has an sRGB chunk: its values encode light by the sRGB curve, "
                        "but are read as linear: give --transfer srgb"));
  EXPECT_EQ(RunCli("extract " + Quoted(srgb) + " --transfer linear").err, "");
  // In a batch, once, and counted for the others.
  fs::copy_file(srgb, dir_ / "srgb2.png");
  fs::copy_file(srgb, dir_ / "srgb3.png");
  const CliResult batch = RunCli("extract " + Quoted(srgb) + " " + Quoted(dir_ / "srgb2.png") + " " +
                                 Quoted(dir_ / "srgb3.png") + " --out " + Quoted(dir_ / "csv"));
  EXPECT_EQ(batch.err, "lasertwin: warning: " + srgb.string() +
                           ": has an sRGB chunk: its values encode light by the sRGB curve, but are read as linear: "
                           "give --transfer srgb to linearize them (--transfer linear reads them as they are, without "
                           "this warning)\nlasertwin: warning: the same as for " + srgb.string() +
                           " (has an sRGB chunk) holds for 2 more images\n");

  // A float TIFF of counts (ImageJ's 32-bit): named once, with a threshold in its units.
  Image<float> counts(64, 48, 1, 0.f);
  for (int y = 0; y < counts.height; ++y)
    for (int x = 0; x < counts.width; ++x) counts.At(x, y) = float(4000 * std::exp(-0.5 * (x - 20) * (x - 20) / 4.0));
  WriteImage(dir_ / "counts.tif", counts);
  EXPECT_THAT(RunCli("extract " + Quoted(dir_ / "counts.tif")).err,
              HasSubstr("note: " + (dir_ / "counts.tif").string() + ": a float image whose samples reach 4000, not 0..1"));

  const fs::path stack = dir_ / "stack.tif";
  {
    const Image<uint8_t> frame = StripeImage();
    OIIO::ImageSpec spec(frame.width, frame.height, 1, OIIO::TypeDesc::UINT8);
    OIIO::ImageSpec specs[2] = {spec, spec};
    auto out = OIIO::ImageOutput::create(stack.string());
    ASSERT_TRUE(out && out->open(stack.string(), 2, specs));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, frame.pixels.data()));
    ASSERT_TRUE(out->open(stack.string(), spec, OIIO::ImageOutput::AppendSubimage));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, frame.pixels.data()));
    ASSERT_TRUE(out->close());
  }
  ExpectInputError(Quoted(stack), stack.string() + ": holds 2 images of 64x48 (pages or frames)");
}

// Frames of one camera share a size: an image of another size among them is
// extracted, and named with both sizes.
TEST_F(ExtractCommand, AnImageOfAnotherSizeIsNamed) {
  WriteImage(dir_ / "a.png", StripeImage());
  WriteImage(dir_ / "b.png", Image<uint8_t>(32, 20, 1, 0));
  WriteImage(dir_ / "c.png", StripeImage());
  const CliResult r = RunCli("extract " + Quoted(dir_ / "a.png") + " " + Quoted(dir_ / "b.png") + " " +
                             Quoted(dir_ / "c.png") + " --out " + Quoted(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("warning: " + (dir_ / "b.png").string() + " is 32x20, the first image (" +
                               (dir_ / "a.png").string() + ") 64x48"));
  EXPECT_THAT(r.err, Not(HasSubstr((dir_ / "c.png").string() + " is")));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "b.csv"));
  EXPECT_THAT(ReadFile(dir_ / "out" / "c.csv"), HasSubstr("20.0000,0.0000,"));
}

TEST_F(ExtractCommand, RoiOutsideTheImage) {
  const fs::path p = dir_ / "mono.png";
  WriteImage(p, StripeImage());
  ExpectInputError(Quoted(p) + " --roi 40,0,30,10", p.string() + ": ROI 40,0,30,10 is not inside the 64x48 image");
  ExpectInputError(Quoted(p) + " --roi -1,0,10,10", "option roi: must start inside the image");
}

TEST_F(ExtractCommand, NaNInFloatImage) {
  Image<float> img(16, 8, 1, 0.0f);
  img.At(3, 5) = std::nanf("");
  const fs::path p = dir_ / "nan.exr";
  WriteImage(p, img);
  ExpectInputError(Quoted(p), p.string() + ": image row 5 holds NaN or infinite values");
}

TEST_F(ExtractCommand, UnknownMethodAndSeveralImages) {
  const fs::path p = dir_ / "mono.png";
  WriteImage(p, StripeImage());
  ExpectInputError(Quoted(p) + " --method fastest",
                   "--method: unknown extraction method 'fastest' (expected max, com, multicom or steger)");
}

// --threshold and --high-threshold take finite numbers: NaN stands for their
// default (10% of full scale, twice the threshold), so a typed "nan" used to
// run silently with the default instead of failing.
TEST_F(ExtractCommand, NonFiniteThresholdsAreRefused) {
  const fs::path p = dir_ / "mono.png";
  WriteImage(p, StripeImage());
  for (const std::string option : {"--threshold", "--high-threshold"}) {
    for (const std::string value : {"nan", "inf", "-inf"}) {
      CliResult r = RunCli("extract " + Quoted(p) + " " + option + " " + value);
      EXPECT_EQ(r.exit_code, 2) << option << " " << value << "\n" << r.err;
      EXPECT_EQ(r.out, "") << option << " " << value;
      const std::string expected = option == "--threshold" ? "expected a finite number or 'auto', got '"
                                                           : "expected a finite number, got '";
      EXPECT_THAT(r.err, HasSubstr(option + ": " + expected + value + "'"));
    }
  }
  CliResult r = RunCli("extract " + Quoted(p) + " --threshold 100 --high-threshold 150");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// A batch goes on past a bad image: the good images before and after it get
// their CSV files, the bad one is named and gets none, and the command then
// fails as a whole (exit 2) saying how many failed.
TEST_F(ExtractCommand, SeveralImagesWithABadOne) {
  const fs::path first = dir_ / "a.png", last = dir_ / "c.png", bad = dir_ / "b.png";
  WriteImage(first, StripeImage());
  WriteImage(last, StripeImage());
  WriteBytes(bad, "nope");
  const fs::path out = dir_ / "csv";
  // A CSV of an earlier run for the bad image must not stay as if it were this run's.
  fs::create_directories(out);
  WriteBytes(out / "b.csv", "u,v,width,strength\n1,2,3,4\n");
  CliResult r = RunCli("extract " + Quoted(first) + " " + Quoted(bad) + " " + Quoted(last) + " --out " + Quoted(out));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_THAT(r.err, HasSubstr("lasertwin: error: " + bad.string() + ": cannot read image"));
  EXPECT_THAT(r.err, HasSubstr("lasertwin: error: 1 of 3 images failed"));
  EXPECT_THAT(ReadFile(out / "a.csv"), HasSubstr("u,v,width,strength\n20.0000,0.0000,"));
  EXPECT_THAT(ReadFile(out / "c.csv"), HasSubstr("u,v,width,strength\n20.0000,0.0000,"));
  EXPECT_FALSE(fs::exists(out / "b.csv"));
  // Every image bad: no "no stripe points" note on top of the errors.
  r = RunCli("extract " + Quoted(bad) + " " + Quoted(dir_ / "missing.png") + " --out " + Quoted(out));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("2 of 2 images failed"));
  EXPECT_THAT(r.err, Not(HasSubstr("note:")));
  // One bad image with --out FILE: exit 2, and no earlier CSV left in FILE.
  WriteBytes(out / "one.csv", "u,v,width,strength\n1,2,3,4\n");
  r = RunCli("extract " + Quoted(bad) + " --out " + Quoted(out / "one.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr(bad.string() + ": cannot read image"));
  EXPECT_FALSE(fs::exists(out / "one.csv"));
}

// --out FILE.csv in a folder that does not exist is an option error naming --out
// and the path (not an internal error about a temporary file).
TEST_F(ExtractCommand, OutInAMissingFolder) {
  const fs::path p = dir_ / "mono.png";
  WriteImage(p, StripeImage());
  const fs::path out = dir_ / "no" / "such" / "x.csv";
  ExpectInputError(Quoted(p) + " --out " + Quoted(out),
                   "--out: the folder of " + out.string() + " does not exist (" + out.parent_path().string() + ")");
  // A file where the folder should be.
  WriteBytes(dir_ / "plain", "x");
  ExpectInputError(Quoted(p) + " " + Quoted(dir_ / "other.png") + " --out " + Quoted(dir_ / "plain"),
                   "--out: cannot create the output folder " + (dir_ / "plain").string());
}

// One image with --out naming an existing folder writes FOLDER/<image name>.csv,
// as several images do; a missing folder for several images is created.
TEST_F(ExtractCommand, OutAsAFolder) {
  const fs::path p = dir_ / "mono.png";
  WriteImage(p, StripeImage());
  fs::create_directories(dir_ / "csv");
  CliResult r = RunCli("extract " + Quoted(p) + " --out " + Quoted(dir_ / "csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_THAT(ReadFile(dir_ / "csv" / "mono.csv"), HasSubstr("u,v,width,strength\n20.0000,0.0000,"));

  const fs::path q = dir_ / "other.png";
  WriteImage(q, StripeImage());
  r = RunCli("extract " + Quoted(p) + " " + Quoted(q) + " --out " + Quoted(dir_ / "new" / "csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "new" / "csv" / "mono.csv"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "new" / "csv" / "other.csv"));

  // A file name in an existing folder is the CSV itself.
  r = RunCli("extract " + Quoted(p) + " --out " + Quoted(dir_ / "csv" / "x.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(ReadFile(dir_ / "csv" / "x.csv"), HasSubstr("u,v,width,strength\n20.0000,0.0000,"));
}

// A thin stripe (one bright pixel per row, its neighbours at a third) is found
// in every row with the default --min-width, by every peak method; isolated
// hot pixels beside it are still rejected and counted in the note.
TEST_F(ExtractCommand, ThinStripeKeptHotPixelsRejected) {
  Image<uint8_t> img(64, 40, 1, 0);
  for (int y = 0; y < img.height; ++y) {
    const int c = 20 + y / 8;  // steps one column every 8 rows
    img.At(c - 1, y) = 60, img.At(c, y) = 200, img.At(c + 1, y) = 60;  // FWHM 1.36 px
  }
  for (int y = 3; y < img.height; y += 8) img.At(45, y) = 255;  // hot pixels, 5 rows apart
  const fs::path p = dir_ / "thin.png";
  WriteImage(p, img);
  for (const char* method : {"max", "com", "multicom"}) {
    SCOPED_TRACE(method);
    CliResult r = RunCli("extract " + Quoted(p) + " --method " + method);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1 + img.height) << r.out;
    EXPECT_THAT(r.out, ::testing::Not(HasSubstr("\n45.")));
    EXPECT_THAT(r.err, HasSubstr("note: 5 candidate peaks were narrower than --min-width 1.5 px without continuing"));
  }
}

// --bayer: a raw mosaic of a red laser is found in every row once demosaiced
// (without it, every peak is narrower than --min-width); an unknown pattern or
// a colour image is an error.
TEST_F(ExtractCommand, BayerMosaic) {
  Image<uint16_t> raw(64, 48, 1, 0);
  const double gain[2][2] = {{1.0, 0.25}, {0.25, 0.05}};  // RGGB
  for (int y = 0; y < raw.height; ++y)
    for (int x = 0; x < raw.width; ++x)
      raw.At(x, y) = uint16_t(std::lround(3000 * gain[y & 1][x & 1] * std::exp(-0.5 * (x - 20.3) * (x - 20.3) / 4.0)));
  const fs::path p = dir_ / "raw.png";
  WriteImage(p, raw);
  CliResult before = RunCli("extract " + Quoted(p) + " --threshold 300");
  ASSERT_EQ(before.exit_code, 0) << before.err;
  EXPECT_EQ(before.out, "u,v,width,strength\n");
  // Not silent: the rejected peaks are counted and the option named.
  EXPECT_THAT(before.err, HasSubstr("lasertwin: note: 48 candidate peaks were narrower than --min-width 1.5 px without "
                                    "continuing on the adjacent search lines and rejected (hot pixels or noise spikes; "
                                    "lower --min-width to keep them)"));
  CliResult steger = RunCli("extract " + Quoted(p) + " --threshold 300 --method steger --width 30");
  EXPECT_THAT(steger.err, HasSubstr("and --width (30 px): steger finds only stripes of about that width"));
  CliResult r = RunCli("extract " + Quoted(p) + " --threshold 300 --bayer rggb");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1 + raw.height) << r.out;
  EXPECT_THAT(r.out, HasSubstr("\n20.3"));
  ExpectInputError(Quoted(p) + " --bayer rgb", "--bayer: unknown Bayer pattern 'rgb' (expected none, rggb, bggr, grbg or gbrg)");
  Image<uint8_t> rgb(16, 8, 3, 0);
  const fs::path colour = dir_ / "colour.png";
  WriteImage(colour, rgb);
  ExpectInputError(Quoted(colour) + " --bayer gbrg", colour.string() + ": a Bayer mosaic (gbrg) has one channel but the image has 3");
}

}  // namespace
}  // namespace lt::test

// One synthetic stripe written in the forms real cameras and their tools write
// (PNG, PGM, TIFF, EXR, BMP, JPEG; 8, 10/12, 16 bits, float) extracts as the
// plain 16-bit PNG does, within each form's quantisation; what files declare
// (sBIT, colour tags, Orientation) sets the default threshold or is named
// (docs/extraction.md, "Image files from real cameras").
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <fstream>
#include <map>

#include "core/image_io.h"
#include "error_of.h"
#include "pipeline/capture_folder.h"
#include "pipeline/image_file_facts.h"
#include "pipeline/stripe_extractor.h"
#include "pipeline/synthetic_stripes.h"
#include "png_chunk_util.h"
#include "scan_test_util.h"

namespace lt {
namespace {

namespace fs = std::filesystem;

class ImageFileForms : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           (std::string("lt_image_forms_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// The stripe's light, 0..0.85 of full scale.
Image<float> Light() {
  SyntheticFrame f;
  f.width = 64, f.height = 48;
  SyntheticStripe s;
  s.u0 = 30.3, s.v0 = 0, s.angle_rad = 0.1, s.sigma = 1.5, s.amplitude = 0.85;
  f.stripes.push_back(s);
  return RenderSyntheticFrame(f);
}

Image<float> Scaled(const Image<float>& light, double full) {
  Image<float> out = light;
  for (float& v : out.pixels) v = float(v * full);
  return out;
}

// com centres by row of the file as extract reads it.
std::map<double, double> CentresOf(const fs::path& path, ExtractionOptions o = {}) {
  ImageFileFacts facts;
  AnyImage img = ReadImage(path, AlphaChannel::kDrop, &facts);
  StripeExtractor extractor(OptionsForImageFile(o, facts));
  std::map<double, double> u_by_row;
  for (const StripePoint& p : extractor.Extract(img)) u_by_row[p.v] = p.u;
  return u_by_row;
}

// Largest |u - u_reference| over rows; every row of the reference must be there.
double LargestDifference(const std::map<double, double>& got, const std::map<double, double>& ref) {
  EXPECT_EQ(got.size(), ref.size());
  double largest = 0;
  for (const auto& [v, u] : ref) {
    auto it = got.find(v);
    if (it == got.end()) return INFINITY;
    largest = std::max(largest, std::abs(it->second - u));
  }
  return largest;
}

// Writes `light` (0..1) with OpenImageIO as `type`, with an int attribute.
void WriteAs(const fs::path& path, const Image<float>& light, OIIO::TypeDesc type, const char* name = nullptr,
             int value = 0, const char* channel = nullptr) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(light.width, light.height, 1, type);
  if (name) spec.attribute(name, value);
  if (channel) spec.channelnames = {channel};
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, light.pixels.data()));
  ASSERT_TRUE(out->close());
}

// A binary PGM (P5) of maxval 4095: 16-bit big-endian samples.
void WritePgm12(const fs::path& path, const Image<float>& light) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << light.width << " " << light.height << "\n4095\n";
  for (float v : light.pixels) {
    const int dn = int(std::lround(v * 4095));
    out.put(char(dn >> 8)).put(char(dn & 255));
  }
}

TEST_F(ImageFileForms, EveryFormGivesThePlainPngsCentres) {
  const Image<float> light = Light();
  WriteImage(dir_ / "ref.png", QuantizeImage<uint16_t>(Scaled(light, 65535)));
  const std::map<double, double> ref = CentresOf(dir_ / "ref.png");
  ASSERT_EQ(ref.size(), 48u);

  WriteImage(dir_ / "8.png", QuantizeImage<uint8_t>(Scaled(light, 255)));
  WriteImage(dir_ / "8.bmp", QuantizeImage<uint8_t>(Scaled(light, 255)));
  WritePgm12(dir_ / "12.pgm", light);
  WriteAs(dir_ / "12.tif", light, OIIO::TypeDesc::UINT16, "oiio:BitsPerSample", 12);
  WriteAs(dir_ / "10.tif", light, OIIO::TypeDesc::UINT16, "oiio:BitsPerSample", 10);
  WriteAs(dir_ / "f.tif", light, OIIO::TypeDesc::FLOAT);
  WriteAs(dir_ / "y.exr", light, OIIO::TypeDesc::HALF, nullptr, 0, "Y");
  WriteAs(dir_ / "r.exr", light, OIIO::TypeDesc::FLOAT, nullptr, 0, "R");
  WriteAs(dir_ / "grey.jpg", light, OIIO::TypeDesc::UINT8, "CompressionQuality", 95);
  // Quantisation steps of the forms: 8-bit 1/255 of full scale, 10-bit 1/1023,
  // 12-bit 1/4095, half 2^-11 relative; JPEG's blocks add more.
  const struct {
    const char* file;
    double tolerance_px;
  } forms[] = {{"8.png", 0.01},  {"8.bmp", 0.01}, {"12.pgm", 0.002}, {"12.tif", 0.002}, {"10.tif", 0.004},
               {"f.tif", 0.0005}, {"y.exr", 0.002}, {"r.exr", 0.0005}, {"grey.jpg", 0.05}};
  for (const auto& form : forms) {
    EXPECT_LE(LargestDifference(CentresOf(dir_ / form.file), ref), form.tolerance_px) << form.file;
  }
}

// A 16-bit PNG of 12-bit DN stored unscaled and saying so (sBIT 12) is
// extracted as a 12-bit frame: the default threshold is 10% of 4095, not of
// 65535 (under which its brightest, 3482, gave no point at all).
TEST_F(ImageFileForms, SbitTwelveBitsStoredUnscaledSetTheDefaultThreshold) {
  const Image<float> light = Light();
  WriteImage(dir_ / "ref.png", QuantizeImage<uint16_t>(Scaled(light, 65535)));
  WriteImage(dir_ / "12.png", QuantizeImage<uint16_t>(Scaled(light, 4095)));
  test::InsertPngChunk(dir_ / "12.png", "sBIT", std::string(1, char(12)));
  ImageFileFacts facts;
  ReadImage(dir_ / "12.png", AlphaChannel::kDrop, &facts);
  EXPECT_DOUBLE_EQ(OptionsForImageFile({}, facts).threshold, 409.5);
  EXPECT_LE(LargestDifference(CentresOf(dir_ / "12.png"), CentresOf(dir_ / "ref.png")), 0.002);
  ExtractionOptions given;
  given.threshold = 5000;  // a given threshold is kept
  EXPECT_EQ(OptionsForImageFile(given, facts).threshold, 5000);
  StripeExtractor as_16_bit{ExtractionOptions{}};  // the old reading: 10% of 65535
  EXPECT_TRUE(as_16_bit.Extract(ReadImage(dir_ / "12.png")).empty());
  ExtractionOptions srgb;
  srgb.transfer = Transfer::kSrgb;
  EXPECT_NE(test::ErrorOf([&] { CentresOf(dir_ / "12.png", srgb); }).find("--transfer"), std::string::npos);
}

TEST(ImageFileWarnings, NameTheTagAndTheOptionThatFollowsIt) {
  ImageFileFacts f;
  EXPECT_TRUE(ImageFileWarnings(f, false).empty());
  f.encoding = "an sRGB chunk";
  ASSERT_EQ(ImageFileWarnings(f, false).size(), 1u);
  EXPECT_NE(ImageFileWarnings(f, false)[0].find("give --transfer srgb"), std::string::npos);
  EXPECT_TRUE(ImageFileWarnings(f, true).empty());  // --transfer given, linear or not
  f.encoding = "a gAMA chunk (gamma 1.8)", f.gamma = 1.8;
  EXPECT_NE(ImageFileWarnings(f, false)[0].find("--transfer gamma=1.8"), std::string::npos);
  f = {};
  f.orientation = 6;
  ASSERT_EQ(ImageFileWarnings(f, true).size(), 1u);
  EXPECT_NE(ImageFileWarnings(f, true)[0].find("has an Orientation tag of 6 (shown turned 90 degrees clockwise): it is not applied"),
            std::string::npos);
}

// Each text once, on the first file it concerns; the count of the others at the
// end, per text, in text order, "frame" or "frames" as they number.
TEST(ImageFileWarner, EachTextOnceThenTheCountOfTheOthers) {
  std::vector<std::string> said;
  ImageFileWarner w([&](const std::string& line) { said.push_back(line); }, "frame");
  w.Say("a.png", "has X: x");
  w.Say("b.png", "has X: x");
  w.Say("b.png", "has Y: y");
  w.Say("c.png", "has X: x");
  ImageFileFacts tagged;
  tagged.orientation = 3;
  w.Check("c.png", tagged, true);
  w.Check("d.png", tagged, true);
  ASSERT_EQ(said.size(), 3u);
  EXPECT_EQ(said[0], "a.png: has X: x");
  EXPECT_EQ(said[1], "b.png: has Y: y");
  EXPECT_EQ(said[2].rfind("c.png: has an Orientation tag of 3 (shown turned 180 degrees): it is not applied", 0), 0u)
      << said[2];
  said.clear();
  w.SayRepeats();
  ASSERT_EQ(said.size(), 2u);
  EXPECT_EQ(said[0], "the same as for a.png (has X) holds for 2 more frames");
  EXPECT_EQ(said[1], "the same as for c.png (has an Orientation tag of 3 (shown turned 180 degrees)) holds for 1 more frame");
  ImageFileWarner quiet({}, "image");  // no function: nothing said, nothing thrown
  quiet.Say("a.png", "has X: x");
  quiet.Say("b.png", "has X: x");
  quiet.SayRepeats();
}

// A float image of counts (ImageJ's 32-bit TIFF, a uint32 TIFF) is above the
// default threshold, 0.1, everywhere: named, with a threshold in its units.
TEST(ImageFileNotes, FloatImagesOfCountsAreNamed) {
  EXPECT_EQ(FloatScaleNote(1.0), "");
  EXPECT_EQ(FloatScaleNote(56000), "a float image whose samples reach 56000, not 0..1 (counts stored as float, or "
                                   "32-bit integers): the default threshold, 0.1, assumes 0..1; give --threshold in "
                                   "its units (e.g. 5600, 10% of that)");
}

// A capture folder of 8- and 16-bit frames: thresholds and black level would
// differ from frame to frame. An error naming both files.
TEST_F(ImageFileForms, ACaptureOfTwoSampleTypesIsAnError) {
  WriteImage(dir_ / "f1.png", Image<uint8_t>(8, 6, 1, 10));
  WriteImage(dir_ / "f2.png", Image<uint16_t>(8, 6, 1, 10));
  const std::string e = test::ErrorOf([&] { ReadCaptureFolder(dir_); });
  EXPECT_NE(e.find("f2.png: the image is 16-bit but f1.png, the first frame, is 8-bit"), std::string::npos) << e;
}

// scan: a capture whose manifest and rig.json give no bit depth, of 10-bit DN
// in 16-bit PNGs with an sBIT chunk of 10: the frames' bit depth is 10
// (threshold 10% of 1023), so the stripe (1000 DN) is found; without the
// chunk, 10% of 65535 finds no point.
TEST(ImageFileScan, SbitGivesTheBitDepthNothingElseGives) {
  using namespace scan_test;
  SyntheticRun run = MakeRun("sbit_depth", 1);
  nlohmann::json rig = nlohmann::json::parse(std::ifstream(run.dir / "rig.json"));
  rig["image_sensor"].erase("bit_depth");
  std::ofstream(run.dir / "rig.json") << rig.dump(2);
  std::ofstream(run.dir / "manifest.jsonl") << R"({"index":0,"files":{"image":"frames/000000.png"}})" << "\n";
  auto quiet = [](const std::string&) {};
  EXPECT_EQ(ScanRun(run.dir, ScanOptions{}, quiet).triangulated, 0);
  test::InsertPngChunk(run.dir / "frames/000000.png", "sBIT", std::string(1, char(10)));
  const ScanSummary s = ScanRun(run.dir, ScanOptions{}, quiet);
  EXPECT_GE(s.triangulated, 150);
  for (const ScanPoint& p : ReadScanCsv(run.dir / "centers/000000.csv")) {
    ASSERT_TRUE(p.p_in_cam);
    EXPECT_LT(ErrorInPixels(run, 0, p), 0.01);
  }
}

// A capture whose frames carry an sRGB chunk: scan says so once, naming the
// first frame's file and --transfer (as extract does), not once per frame, and
// at the end for how many more frames it holds (before: no count); with
// --transfer given (even linear) it says nothing.
TEST(ImageFileScan, TransferTagIsWarnedOnceAScan) {
  using namespace scan_test;
  SyntheticRun run = MakeRun("srgb_tag", 1);
  // A second laser frame, a copy of the first.
  std::ifstream manifest(run.dir / "manifest.jsonl");
  nlohmann::json dim;
  manifest >> dim;
  dim["index"] = 2;
  dim["files"]["image"] = "frames/000002.png";
  std::ofstream(run.dir / "manifest.jsonl", std::ios::app) << dim.dump() << "\n";
  fs::copy_file(run.dir / "frames/000000.png", run.dir / "frames/000002.png");
  for (const char* f : {"frames/000000.png", "frames/000002.png"}) {
    test::InsertPngChunk(run.dir / f, "sRGB", std::string(1, char(0)));
  }
  std::vector<std::string> warnings;
  auto collect = [&](const std::string& w) { warnings.push_back(w); };
  ScanRun(run.dir, ScanOptions{}, collect);
  int tagged = 0, counted = 0;
  for (const std::string& w : warnings) {
    if (w.find("sRGB") == std::string::npos) continue;
    if (w.rfind("the same as for ", 0) == 0) {
      ++counted;
      EXPECT_EQ(w, "the same as for " + (run.dir / "frames/000000.png").string() +
                       " (has an sRGB chunk) holds for 1 more frame");
      continue;
    }
    ++tagged;
    EXPECT_NE(w.find("000000.png: "), std::string::npos) << w;
    EXPECT_NE(w.find("--transfer"), std::string::npos) << w;
  }
  EXPECT_EQ(tagged, 1);
  EXPECT_EQ(counted, 1);
  warnings.clear();
  ScanOptions given;
  given.transfer_given = true;
  ScanRun(run.dir, given, collect);
  for (const std::string& w : warnings) EXPECT_EQ(w.find("sRGB"), std::string::npos) << w;
}

}  // namespace
}  // namespace lt

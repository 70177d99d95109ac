// Stripe extraction on frames encoded as cameras and tools deliver them
// (docs/extraction.md, "Encoded images"): 8-bit sRGB and gamma 1/2.2, JPEG at
// quality 50-95 (grey, and a red laser in RGB with 4:2:0 chroma subsampling),
// 12-bit data LSB- and MSB-aligned in 16 bits with and without a black level,
// and a saturated stripe with a halo or CCD smear. The light is rendered linear
// (stripe_frames.h, in units of the full scale), then encoded; the truth is the
// centre line (for a tail profile, its peak). Default options apart from those
// a row names. Per method: search lines with a point within 3 px of the
// truth / lines, +points matched to none, RMS / max |error| (px), and the mean
// width (FWHM, px) reported.
//
//   build/bin/exp_stripe_encodings
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "core/image_io.h"
#include "pipeline/extract_transfer.h"
#include "tools/experiments/stripe_frames.h"

namespace {

using namespace exp_stripes;
using lt::Transfer;

// Linear light (0..1 of full scale) encoded to `bits` (8 or 16) through the
// inverse of `transfer`, scaled by `scale` and offset by `black` (DN), rounded
// and clipped to [0, max DN].
template <typename T>
lt::Image<T> Encode(const lt::Image<float>& light, Transfer transfer, double gamma, double scale, double black,
                    double max_dn) {
  lt::Image<T> out(light.width, light.height, light.channels, T(0));
  for (int y = 0; y < light.height; ++y)
    for (int x = 0; x < light.width; ++x)
      for (int c = 0; c < light.channels; ++c) {
        double e = std::clamp(double(light.At(x, y, c)), 0.0, 1.0);
        if (transfer == Transfer::kSrgb) e = e <= 0.0031308 ? 12.92 * e : 1.055 * std::pow(e, 1 / 2.4) - 0.055;
        if (transfer == Transfer::kGamma) e = std::pow(e, 1 / gamma);
        out.At(x, y, c) = T(std::clamp(std::round(black + e * scale), 0.0, max_dn));
      }
  return out;
}

// The image written as a JPEG of `quality` (OpenImageIO, libjpeg; RGB with
// `subsampling`) and read back.
lt::AnyImage ThroughJpeg(const lt::Image<uint8_t>& im, int quality, const char* subsampling) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("exp_stripe_encodings_" + std::to_string(getpid()) + ".jpg"))
          .string();
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(im.width, im.height, im.channels, OIIO::TypeDesc::UINT8);
  spec.attribute("Compression", "jpeg:" + std::to_string(quality));
  if (im.channels == 3) spec.attribute("jpeg:subsampling", subsampling);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, im.pixels.data())) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    std::exit(2);
  }
  out->close();
  lt::AnyImage back = lt::ReadImage(path);
  std::filesystem::remove(path);
  return back;
}

struct Options {
  Transfer transfer = Transfer::kLinear;
  double gamma = 2.2;
  double threshold = lt::ExtractionOptions::kAuto;
  double background = 0;
  int channel = -1;
  bool local = false;
};

void Row(const std::string& name, const Frame& f, const lt::AnyImage& img, const Options& opt = {},
         double match = 3) {
  std::printf("| %s |", name.c_str());
  for (auto m : {lt::ExtractionMethod::kMax, lt::ExtractionMethod::kCom, lt::ExtractionMethod::kMultiCom,
                 lt::ExtractionMethod::kSteger}) {
    lt::ExtractionOptions o;
    o.method = m;
    o.transfer = opt.transfer;
    o.gamma = opt.gamma;
    o.threshold = opt.threshold;
    o.background = opt.background;
    o.channel = opt.channel;
    if (opt.local) o.background_mode = lt::BackgroundMode::kLocal;
    lt::StripeExtractor extractor(o);
    const Cell c = Score(f, extractor.Extract(img), match);
    std::printf(" %d/%d", c.found, c.lines);
    if (c.unmatched) std::printf(" +%d", c.unmatched);
    if (c.found) std::printf(", %.3f / %.3f, w %.1f", c.rms, c.max_abs, c.width);
    std::printf(" |");
  }
  std::printf("\n");
}

Frame One(Profile p, double noise = 0.002, double angle = 5) {
  Frame f;
  f.stripes.push_back({80.3, 48, angle, std::move(p)});
  f.noise = noise;
  return f;
}

// Rows for an 8-bit encoding: as delivered (default options), and linearized
// with the matching --transfer.
void EightBit(const std::string& name, const Frame& f, Transfer transfer, double gamma = 2.2) {
  const lt::Image<float> light = Render(f);
  const lt::AnyImage img = Encode<uint8_t>(light, transfer, gamma, 255, 0, 255);
  Row(name, f, img);
  if (transfer == Transfer::kLinear) return;
  Options o;
  o.transfer = transfer;
  o.gamma = gamma;
  Row(name + (transfer == Transfer::kSrgb ? ", `--transfer srgb`" : ", `--transfer gamma=2.2`"), f, img, o);
}

}  // namespace

int main() {
  std::printf("| frame | max | com | multicom | steger |\n| --- | --- | --- | --- | --- |\n");
  // Gamma-encoded 8-bit: symmetric Gaussians, a dim stripe on ambient light,
  // asymmetric (subsurface tail) profiles; truth for a tail: its peak.
  for (double s : {1.0, 2.0}) {
    char name[96];
    std::snprintf(name, sizeof name, "sigma %.0f, peak 0.8", s);
    EightBit(std::string("8-bit linear, ") + name, One(Gauss(0.8, s)), Transfer::kLinear);
    EightBit(std::string("8-bit sRGB, ") + name, One(Gauss(0.8, s)), Transfer::kSrgb);
  }
  EightBit("8-bit gamma 1/2.2, sigma 2, peak 0.8", One(Gauss(0.8, 2)), Transfer::kGamma);
  {
    Frame f = One(Gauss(0.3, 2));
    f.level = 0.03;
    EightBit("8-bit linear, sigma 2, peak 0.3 on ambient 0.03", f, Transfer::kLinear);
    EightBit("8-bit sRGB, sigma 2, peak 0.3 on ambient 0.03", f, Transfer::kSrgb);
  }
  for (double tail : {2.0, 6.0}) {
    char name[96];
    std::snprintf(name, sizeof name, "tail %.0f px at 0.5, sigma 1.5 (truth: the peak)", tail);
    Frame f = One(Tail(0.8, 1.5, tail, 0.5));
    const lt::Image<float> light = Render(f);
    Row(std::string("8-bit linear, ") + name, f, Encode<uint8_t>(light, Transfer::kLinear, 0, 255, 0, 255), {}, 10);
    const lt::AnyImage srgb = Encode<uint8_t>(light, Transfer::kSrgb, 0, 255, 0, 255);
    Row(std::string("8-bit sRGB, ") + name, f, srgb, {}, 10);
    Options o;
    o.transfer = Transfer::kSrgb;
    Row(std::string("8-bit sRGB, ") + name + ", `--transfer srgb`", f, srgb, o, 10);
  }
  // JPEG: grey, and a red laser in RGB (G and B a tenth and a twentieth of R,
  // on a grey ambient of 0.02) with 4:2:0 chroma subsampling, --channel 0.
  for (int q : {50, 75, 90, 95}) {
    Frame f = One(Gauss(0.8, 2));
    const lt::Image<float> light = Render(f);
    const lt::AnyImage jpg = ThroughJpeg(Encode<uint8_t>(light, Transfer::kSrgb, 0, 255, 0, 255), q, "");
    char name[96];
    std::snprintf(name, sizeof name, "JPEG %d, grey sRGB, sigma 2", q);
    Row(name, f, jpg);
    Options o;
    o.transfer = Transfer::kSrgb;
    Row(std::string(name) + ", `--transfer srgb`", f, jpg, o);
  }
  for (int q : {50, 75, 90, 95}) {
    Frame f = One(Gauss(0.8, 2));
    const lt::Image<float> red = Render(f);
    lt::Image<float> rgb(red.width, red.height, 3, 0.0f);
    for (int y = 0; y < red.height; ++y)
      for (int x = 0; x < red.width; ++x) {
        const float r = red.At(x, y);
        rgb.At(x, y, 0) = r + 0.02f, rgb.At(x, y, 1) = 0.1f * r + 0.02f, rgb.At(x, y, 2) = 0.05f * r + 0.02f;
      }
    const lt::AnyImage jpg = ThroughJpeg(Encode<uint8_t>(rgb, Transfer::kSrgb, 0, 255, 0, 255), q, "4:2:0");
    char name[96];
    std::snprintf(name, sizeof name, "JPEG %d, red laser RGB 4:2:0, `--channel 0`", q);
    Options o;
    o.channel = 0;
    Row(name, f, jpg, o);
    o.transfer = Transfer::kSrgb;
    Row(std::string(name) + " `--transfer srgb`", f, jpg, o);
  }
  // 12-bit data in 16-bit samples: LSB-aligned (< 4096), MSB-aligned (x 16),
  // with a black level of 64 DN of 4095; sigma 2, peak 0.5 of the 12-bit range.
  {
    Frame f = One(Gauss(0.5, 2), 0.001);
    const lt::Image<float> light = Render(f);
    const lt::AnyImage lsb = Encode<uint16_t>(light, Transfer::kLinear, 0, 4095, 0, 4095);
    Row("12-bit LSB-aligned (< 4096)", f, lsb);
    Options o;
    o.threshold = 409.5;
    Row("12-bit LSB-aligned, `--threshold 409.5`", f, lsb, o);
    Row("12-bit MSB-aligned (x 16)", f, Encode<uint16_t>(light, Transfer::kLinear, 0, 4095 * 16, 0, 65535));
    const lt::AnyImage black = Encode<uint16_t>(light, Transfer::kLinear, 0, (4095 - 64) * 16, 64 * 16, 65535);
    Row("12-bit MSB-aligned, black level 64 DN", f, black);
    o = {};
    o.background = 1024;
    Row("12-bit MSB-aligned, black level 64 DN, `--background 1024`", f, black, o);
  }
  {
    // A 10-bit sensor's black level of 64 of 1023 (6.3%), x 64, read noise 0.5%
    // of its range, a stripe of 0.1 above it: the threshold (10% of 65535)
    // counts from 0, 3.7% above the black level.
    Frame f = One(Gauss(0.1, 2), 0.005);
    const lt::AnyImage black = Encode<uint16_t>(Render(f), Transfer::kLinear, 0, (1023 - 64) * 64, 64 * 64, 65535);
    Row("10-bit MSB-aligned, black level 64 of 1023, peak 0.1, noise 0.5%", f, black);
    Options o;
    o.background = 4096;
    Row("the same, `--background 4096`", f, black, o);
    o.threshold = 4096 + 6553.5;
    Row("the same, `--background 4096 --threshold 10649.5`", f, black, o);
  }
  // Blooming and smear on a stripe saturated 10x (8-bit linear, sigma 1.5):
  // a symmetric halo 0.15 exp(-|d| / 6); CCD smear: each column raised by its
  // light summed over the frame, scaled to 0.15 of full scale at the most.
  {
    Frame f = One([](double d) { return 10 * std::exp(-d * d / (2 * 1.5 * 1.5)) + 0.15 * std::exp(-std::abs(d) / 6); });
    Row("saturated 10x, halo 0.15, 6 px", f, Encode<uint8_t>(Render(f), Transfer::kLinear, 0, 255, 0, 255));
  }
  for (double angle : {5.0, 20.0}) {
    Frame f = One(Gauss(10, 1.5), 0.002, angle);
    lt::Image<float> light = Render(f);
    std::vector<double> column(light.width, 0.0);
    double most = 0;
    for (int x = 0; x < light.width; ++x) {
      for (int y = 0; y < light.height; ++y) column[x] += light.At(x, y);
      most = std::max(most, column[x]);
    }
    for (int y = 0; y < light.height; ++y)
      for (int x = 0; x < light.width; ++x) light.At(x, y) += float(0.15 * column[x] / most);
    const lt::AnyImage img = Encode<uint8_t>(light, Transfer::kLinear, 0, 255, 0, 255);
    char name[96];
    std::snprintf(name, sizeof name, "saturated 10x, %.0f deg, CCD smear 0.15", angle);
    Row(name, f, img);
    Options o;
    o.local = true;
    Row(std::string(name) + ", `--background local`", f, img, o);
  }
  {
    // A saturated glint at (30, 20) whose smear runs down its column (0.3).
    Frame f = One(Gauss(10, 1.5));
    lt::Image<float> light = Render(f);
    for (int y = 0; y < light.height; ++y)
      for (int x = 29; x <= 31; ++x) light.At(x, y) += float(std::hypot(x - 30, y - 20) < 3 ? 10 : x == 30 ? 0.3 : 0.1);
    Row("saturated 10x, glint with a smear column 0.3", f,
        Encode<uint8_t>(light, Transfer::kLinear, 0, 255, 0, 255));
  }
  return 0;
}

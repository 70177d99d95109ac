#include "core/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/png_chunks.h"
#include "core/text_fields.h"

namespace lt {

namespace {

// A file of several frames of one size (a multi-page TIFF stack, an animated
// GIF, a multi-part EXR) is an error: reading its first would drop the others
// unseen. A second image of another size (a TIFF's thumbnail page) is not a
// frame and is left out.
void RefuseSeveralFrames(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, const std::filesystem::path& path) {
  // (OpenImageIO 2.4's TIFF reader does not claim "multiimage": seek.)
  if (!in.seek_subimage(1, 0)) {
    if (!in.seek_subimage(0, 0)) throw InputError(path.string(), "cannot read image: " + in.geterror());
    return;
  }
  const bool same = in.spec().width == spec.width && in.spec().height == spec.height;
  int frames = 2;
  while (same && frames < 100000 && in.seek_subimage(frames, 0)) ++frames;
  if (!in.seek_subimage(0, 0)) throw InputError(path.string(), "cannot read image: " + in.geterror());
  if (!same) return;
  throw InputError(path.string(), "holds " + std::to_string(frames) + " images of " + std::to_string(spec.width) + "x" +
                                      std::to_string(spec.height) +
                                      " (pages or frames); one file is one frame here: write each to its own file "
                                      "(e.g. ImageJ's Stack to Images, or oiiotool's --subimage)");
}

// The most pixel data, as held (1, 2 or 4 bytes a sample) or as OpenImageIO
// 2.4's read_image buffers it (at least its read_chunk, 256 rows, at the file's
// sample size), a header's size is believed for: a camera's largest frames (150
// Mpx of 3 float channels) hold under 2 GB. A damaged or hostile header (a
// 69-byte PNG declaring 60000x60000 RGBA at 16 bits, a 42-byte PGM declaring
// 51000000x2) is an error naming it, before gigabytes are allocated (or
// std::bad_alloc) for a decoder that then fails on the first row.
constexpr double kLargestImageBytes = 4e9;
constexpr int kReadChunkRows = 256;

void RefuseDamagedSize(const OIIO::ImageSpec& spec, const std::filesystem::path& path) {
  const double held = spec.format == OIIO::TypeDesc::UINT8 ? 1 : spec.format == OIIO::TypeDesc::UINT16 ? 2 : 4;
  const double sample = std::max(held, double(spec.format.size()));
  const double bytes = double(spec.width) * std::max(spec.height, kReadChunkRows) * spec.nchannels * sample;
  if (bytes <= kLargestImageBytes) return;
  char gb[32];
  std::snprintf(gb, sizeof gb, "%.1f", bytes / 1e9);
  throw InputError(path.string(), "its header declares " + std::to_string(spec.width) + "x" +
                                      std::to_string(spec.height) + " pixels of " + std::to_string(spec.nchannels) +
                                      (spec.nchannels == 1 ? " channel (" : " channels (") + gb + " GB to read" +
                                      (spec.height < kReadChunkRows ? ", 256 rows at a time" : "") +
                                      "); images above " + FormatNumber(kLargestImageBytes / 1e9) +
                                      " GB are not read (a damaged file?)");
}

std::unique_ptr<OIIO::ImageInput> OpenInput(const std::filesystem::path& path, OIIO::ImageSpec* spec) {
  if (!std::filesystem::exists(path)) throw InputError(path.string(), "no such file");
  if (std::filesystem::is_directory(path)) throw InputError(path.string(), "is a folder, not an image");
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec) && std::filesystem::file_size(path, ec) == 0 && !ec) {
    throw InputError(path.string(), "is empty (0 bytes), not an image");
  }
  // Straight (unassociated) alpha: without this OpenImageIO multiplies PNG's and
  // TIFF's colour by alpha, so a pixel of 200 with alpha 128 would read 100.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) {
    std::string err = OIIO::geterror();
    throw InputError(path.string(), "cannot read image" + (err.empty() ? "" : ": " + err));
  }
  *spec = in->spec();
  if (spec->width <= 0 || spec->height <= 0 || spec->nchannels <= 0) {
    throw InputError(path.string(), "image has zero size (" + std::to_string(spec->width) + "x" +
                                        std::to_string(spec->height) + ", " +
                                        std::to_string(spec->nchannels) + " channels)");
  }
  if (spec->depth > 1) throw InputError(path.string(), "volume images are not supported");
  RefuseDamagedSize(*spec, path);
  RefuseSeveralFrames(*in, *spec, path);
  (void)in->geterror();  // open succeeded: whatever it noted is not a pixel error (see ReadAs)
  return in;
}

// Reads the pixels into `data` as `type`. OpenImageIO 2.4 returns true from
// read_image for a truncated TIFF or JPEG and leaves the missing rows zero, with
// only an error message left behind: that message is an error here too.
void ReadPixels(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, OIIO::TypeDesc type, void* data,
                const std::filesystem::path& path) {
  bool ok;
  {
#if defined(__SANITIZE_ADDRESS__)
    // OpenImageIO 2.4 leaks the error string of a failed PNG read (libpng's
    // longjmp skips its destructor): a library leak, ignored in the sanitizer
    // build. tools/lsan.supp cannot name it: the fast unwinder stops in libstdc++.
    __lsan::ScopedDisabler library_leaks;
#endif
    ok = in.read_image(0, 0, 0, spec.nchannels, type, data);
  }
  std::string err = in.geterror();
  if (!ok || !err.empty()) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    throw InputError(path.string(), "cannot decode image" + (err.empty() ? "" : ": " + err));
  }
}

template <typename T>
Image<T> ReadAs(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                const std::filesystem::path& path) {
  Image<T> img(spec.width, spec.height, spec.nchannels);
  ReadPixels(in, spec, type, img.pixels.data(), path);
  return img;
}

// Reads integer samples in their own type and converts them to float with their
// raw values. (Asking OpenImageIO for UINT8/UINT16/FLOAT instead would rescale:
// an int16 goes through 0..65535 doubled with negatives clamped, a uint32 comes
// back divided by 2^32 - 1.)
template <typename S>
Image<float> ReadRawAsFloat(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                            const std::filesystem::path& path) {
  std::vector<S> raw(size_t(spec.width) * spec.height * spec.nchannels);
  ReadPixels(in, spec, type, raw.data(), path);
  Image<float> img(spec.width, spec.height, spec.nchannels);
  for (size_t i = 0; i < raw.size(); ++i) img.pixels[i] = float(raw[i]);
  return img;
}

// Every sample type other than UINT8/UINT16 as float in the file's own units.
Image<float> ReadFloatRaw(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, const std::filesystem::path& path) {
  switch (spec.format.basetype) {
    case OIIO::TypeDesc::UINT8: return ReadRawAsFloat<uint8_t>(in, spec, OIIO::TypeDesc::UINT8, path);
    case OIIO::TypeDesc::INT8: return ReadRawAsFloat<int8_t>(in, spec, OIIO::TypeDesc::INT8, path);
    case OIIO::TypeDesc::UINT16: return ReadRawAsFloat<uint16_t>(in, spec, OIIO::TypeDesc::UINT16, path);
    case OIIO::TypeDesc::INT16: return ReadRawAsFloat<int16_t>(in, spec, OIIO::TypeDesc::INT16, path);
    case OIIO::TypeDesc::UINT32: return ReadRawAsFloat<uint32_t>(in, spec, OIIO::TypeDesc::UINT32, path);
    case OIIO::TypeDesc::INT32: return ReadRawAsFloat<int32_t>(in, spec, OIIO::TypeDesc::INT32, path);
    case OIIO::TypeDesc::UINT64: return ReadRawAsFloat<uint64_t>(in, spec, OIIO::TypeDesc::UINT64, path);
    case OIIO::TypeDesc::INT64: return ReadRawAsFloat<int64_t>(in, spec, OIIO::TypeDesc::INT64, path);
    default: return ReadAs<float>(in, spec, OIIO::TypeDesc::FLOAT, path);
  }
}

// The image without channel `drop`.
template <typename T>
Image<T> WithoutChannel(const Image<T>& in, int drop) {
  Image<T> out(in.width, in.height, in.channels - 1);
  T* o = out.pixels.data();
  for (size_t p = 0; p < size_t(in.width) * in.height; ++p) {
    for (int c = 0; c < in.channels; ++c) {
      if (c != drop) *o++ = in.pixels[p * size_t(in.channels) + size_t(c)];
    }
  }
  return out;
}

template <typename T>
void Write(const std::filesystem::path& path, const Image<T>& image, OIIO::TypeDesc file_type,
           OIIO::TypeDesc mem_type, const std::vector<std::string>& channel_names) {
  if (image.empty() || image.channels <= 0) throw std::invalid_argument("cannot write an empty image: " + path.string());
  if (image.pixels.size() != size_t(image.width) * image.height * image.channels) {
    throw std::invalid_argument("image buffer size does not match its dimensions: " + path.string());
  }
  WriteAtomically(path, [&](const std::filesystem::path& tmp) {
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) throw std::runtime_error("no image writer for " + path.string() + ": " + OIIO::geterror());
    OIIO::ImageSpec spec(image.width, image.height, image.channels, file_type);
    if (!channel_names.empty()) {
      if (int(channel_names.size()) != image.channels) {
        throw std::invalid_argument("channel name count does not match channels: " + path.string());
      }
      spec.channelnames = channel_names;
    }
    // The pixels are written as given: an alpha channel is straight, not divided out.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    // OpenEXR files otherwise get the time of writing as their capture date, so
    // that the same image written twice differed in its bytes.
    if (std::string_view(out->format_name()) == "openexr") spec.attribute("DateTime", "");
    if (!out->open(tmp.string(), spec)) throw std::runtime_error("cannot create " + tmp.string() + ": " + out->geterror());
    if (!out->write_image(mem_type, image.pixels.data())) {
      throw std::runtime_error("cannot write " + tmp.string() + ": " + out->geterror());
    }
    if (!out->close()) throw std::runtime_error("cannot finish " + tmp.string() + ": " + out->geterror());
  });
}

// The alpha channel: the one the reader marks, else a last channel named A or
// Alpha after grey or RGB ones (OpenImageIO 2.4's GIF reader names its fourth
// channel A but marks channel 4, which does not exist); -1 when none.
int AlphaChannelOf(const OIIO::ImageSpec& spec) {
  const int n = spec.nchannels;
  if (spec.alpha_channel >= 0 && spec.alpha_channel < n) return spec.alpha_channel;
  if ((n == 2 || n == 4) && int(spec.channelnames.size()) == n) {
    const std::string name = Lower(spec.channelnames[size_t(n - 1)]);
    if (name == "a" || name == "alpha") return n - 1;
  }
  return -1;
}

// Whether every sample of every channel but `alpha` (-1: none) is at most
// `full` = 2^bits - 1 and some sample has a bit set below the top `bits` of its
// `container` bits: the declared bits stored unscaled (LSB-aligned). Samples
// shifted to the top bits (the PNG standard's way, by a shift or by repeating
// the high bits) have those low bits clear wherever they are at most `full`, as
// in a dim frame, so all-clear low bits are read as shifted.
template <typename T>
bool StoredUnscaled(const Image<T>& img, int alpha, int bits, int container) {
  const uint32_t full = (1u << bits) - 1, low = (1u << (container - bits)) - 1;
  bool low_bits = false;
  const size_t n = img.pixels.size();
  for (size_t i = 0; i < n; ++i) {
    if (int(i % size_t(img.channels)) == alpha) continue;
    const uint32_t v = uint32_t(img.pixels[i]);
    if (v > full) return false;
    low_bits = low_bits || (v & low) != 0;
  }
  return low_bits;
}

ImageFileFacts FactsOf(const std::filesystem::path& path, const OIIO::ImageSpec& spec, const AnyImage& image,
                       int alpha) {
  ImageFileFacts f;
  f.orientation = spec.get_int_attribute("Orientation", 1);
  if (spec.find_attribute("ICCProfile")) f.encoding = "an ICC profile";
  if (spec.get_int_attribute("Exif:ColorSpace", 0) == 1) f.encoding = "EXIF ColorSpace sRGB";
  const PngChunks png = ReadPngChunks(path);
  if (png.is_png) {
    f.encoding.clear();  // the chunks, read here, say it (OpenImageIO's guess is not used)
    if (png.icc) f.encoding = "an ICC profile";
    if (png.gamma > 0 && std::abs(png.gamma - 1) > 0.01) {
      f.encoding = "a gAMA chunk (gamma " + FormatNumber(png.gamma) + ")";
      f.gamma = png.gamma;
    }
    if (png.srgb) f.encoding = "an sRGB chunk", f.gamma = 0;  // sRGB overrides gAMA (the PNG standard)
    const int container = std::holds_alternative<Image<uint16_t>>(image) ? 16 : std::holds_alternative<Image<uint8_t>>(image) ? 8 : 0;
    if (png.significant_bits > 0 && png.significant_bits < container && png.bit_depth == container) {
      f.significant_bits = png.significant_bits;
      const int bits = png.significant_bits;
      const bool unscaled =  // container 8 or 16: an integer image
          std::visit([&](const auto& img) { return StoredUnscaled(img, alpha, bits, container); }, image);
      if (unscaled) f.unscaled_full_scale = std::ldexp(1.0, bits) - 1;
    }
  }
  return f;
}

}  // namespace

Image<float> ReadImageChannels(const std::filesystem::path& path, const std::vector<std::string>& names) {
  OIIO::ImageSpec spec;
  auto in = OpenInput(path, &spec);
  Image<float> all = ReadFloatRaw(*in, spec, path);
  std::vector<int> index;
  for (const std::string& name : names) {
    int found = -1;
    for (int c = 0; c < spec.nchannels; ++c) {
      if (c < int(spec.channelnames.size()) && spec.channelnames[size_t(c)] == name) found = c;
    }
    if (found < 0) throw InputError(path.string(), "has no channel \"" + name + "\"");
    index.push_back(found);
  }
  Image<float> out(spec.width, spec.height, int(names.size()));
  for (int y = 0; y < spec.height; ++y)
    for (int x = 0; x < spec.width; ++x)
      for (size_t k = 0; k < index.size(); ++k) out.At(x, y, int(k)) = all.At(x, y, index[k]);
  return out;
}

ImageFileSize ReadImageFileSize(const std::filesystem::path& path) {
  OIIO::ImageSpec spec;
  OpenInput(path, &spec);
  const char* type = spec.format == OIIO::TypeDesc::UINT8 ? "8-bit" : spec.format == OIIO::TypeDesc::UINT16 ? "16-bit" : "float";
  return {spec.width, spec.height, spec.nchannels, type};
}

AnyImage ReadImage(const std::filesystem::path& path) { return ReadImage(path, AlphaChannel::kKeep); }

AnyImage ReadImage(const std::filesystem::path& path, AlphaChannel alpha) { return ReadImage(path, alpha, nullptr); }

AnyImage ReadImage(const std::filesystem::path& path, AlphaChannel alpha, ImageFileFacts* facts) {
  OIIO::ImageSpec spec;
  auto in = OpenInput(path, &spec);
  const OIIO::TypeDesc f = spec.format;
  AnyImage image;
  if (f == OIIO::TypeDesc::UINT8) {
    image = ReadAs<uint8_t>(*in, spec, OIIO::TypeDesc::UINT8, path);
  } else if (f == OIIO::TypeDesc::UINT16) {
    image = ReadAs<uint16_t>(*in, spec, OIIO::TypeDesc::UINT16, path);
  } else {
    image = ReadFloatRaw(*in, spec, path);
  }
  const int a = AlphaChannelOf(spec);
  if (facts) *facts = FactsOf(path, spec, image, a);
  if (alpha == AlphaChannel::kDrop && a >= 0 && a < spec.nchannels && spec.nchannels > 1) {
    std::visit([a](auto& img) { img = WithoutChannel(img, a); }, image);
  }
  return image;
}

Image<float> ReadImageFloat(const std::filesystem::path& path) {
  return std::visit(
      [](auto&& img) -> Image<float> {
        Image<float> out(img.width, img.height, img.channels);
        for (size_t i = 0; i < img.pixels.size(); ++i) out.pixels[i] = float(img.pixels[i]);
        return out;
      },
      ReadImage(path));
}

Image<float> ReadImageFloat(const std::filesystem::path& path, std::vector<std::string>* channel_names) {
  OIIO::ImageSpec spec;
  auto in = OpenInput(path, &spec);
  if (channel_names) {
    channel_names->clear();
    for (int c = 0; c < spec.nchannels; ++c) channel_names->push_back(spec.channel_name(c));
  }
  return ReadFloatRaw(*in, spec, path);
}

void WriteImage(const std::filesystem::path& path, const Image<uint8_t>& image) {
  Write(path, image, OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8, {});
}

void WriteImage(const std::filesystem::path& path, const Image<uint16_t>& image) {
  Write(path, image, OIIO::TypeDesc::UINT16, OIIO::TypeDesc::UINT16, {});
}

void WriteImage(const std::filesystem::path& path, const Image<float>& image, bool full_float,
                const std::vector<std::string>& channel_names) {
  Write(path, image, full_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT,
        channel_names);
}

}  // namespace lt

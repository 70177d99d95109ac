// Frame image files as scan, calibrate and extract read them (core/image_io.h:
// ReadImage with its ImageFileFacts, OpenImageIO's decoders and the PNG header
// chunks read here; pipeline/image_file_facts.h: the warnings and notes on what
// the file declares). The first byte's low two bits choose the file's
// extension: .png, .tif, .pgm, .jpg (OpenImageIO picks its decoder by it).
#include <algorithm>

#include "fuzz_common.h"
#include "pipeline/image_file_facts.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kNames[4] = {"frame.png", "frame.tif", "frame.pgm", "frame.jpg"};
  const std::filesystem::path path = lt::fuzz::WriteScratch(kNames[data[0] & 3], data + 1, size - 1);
  lt::fuzz::ExpectCleanErrors([&] {
    // The reader reads headers of up to 4 GB of samples (core/image_io.cpp; above
    // that is an error, tested in tests/core/image_files_test.cpp), more than
    // -rss_limit_mb=2048 allows: a file declaring above 1 GB (at 4 bytes a sample,
    // 256 rows at least, as OpenImageIO buffers a read) is not decoded here.
    const lt::ImageFileSize declared = lt::ReadImageFileSize(path);
    if (double(declared.width) * std::max(declared.height, 256) * declared.channels * 4 > 1e9) return;
    lt::ImageFileFacts facts;
    (void)lt::ReadImage(path, lt::AlphaChannel::kDrop, &facts);
    (void)lt::ImageFileWarnings(facts, false);
    (void)lt::UnscaledBitsNote(facts);
    (void)lt::DeclaredUnscaledBits(facts);
    (void)lt::OptionsForImageFile(lt::ExtractionOptions{}, facts);
  });
  std::filesystem::remove(path);
  return 0;
}

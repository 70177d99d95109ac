// The command line's option values parsed from text: the first byte chooses the
// parser, the rest is the value (--frames, --quat-order, --pose-units, --shutter,
// --method, --axis, --transfer, --background, --weights, --roi, --depth-range,
// --bayer, and a field read as a number).
#include "core/frame_range.h"
#include "core/text_fields.h"
#include "fuzz_common.h"
#include "pipeline/capture_folder.h"
#include "pipeline/demosaic.h"
#include "pipeline/extraction_options.h"
#include "pipeline/plane_id_sheets.h"
#include "pipeline/pose_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string text = lt::fuzz::Text(data + 1, size - 1);
  const std::string where = "--option";
  lt::fuzz::ExpectCleanErrors([&] {
    switch (data[0] % 13) {
      case 0: {
        const lt::FrameRange r = lt::FrameRange::Parse(text);
        for (int count : {0, 1, 7, 1 << 30}) lt::fuzz::ExpectCleanErrors([&] { r.Resolve(count); });
        break;
      }
      case 1: lt::ParseQuaternionOrder(text, where); break;
      case 2: lt::ParsePoseUnits(text, where); break;
      case 3: lt::ParseShutterPattern(text, where); break;
      case 4: lt::ParseMethod(text, where); break;
      case 5: lt::ParseAxis(text, where); break;
      case 6: {
        lt::Transfer transfer;
        double gamma = 0;
        lt::ParseTransfer(text, where, &transfer, &gamma);
        break;
      }
      case 7: {
        double level = 0;
        lt::BackgroundMode mode;
        lt::ParseBackground(text, where, &level, &mode);
        break;
      }
      case 8: lt::ParseNumberList(text, where); break;
      case 9: lt::ParseRoi(text, where); break;
      case 10: lt::ParseDepthRange(text, where); break;
      case 11: lt::ParseBayerPattern(text, where); break;
      default: {
        lt::ParseFiniteNumber(text);
        const auto fields = lt::SplitFields(text, ',');
        for (size_t k = 0; k < fields.size(); ++k) lt::fuzz::ExpectCleanErrors([&] { lt::FiniteField(fields, k, "f:1"); });
        lt::SplitBlanks(text);
      }
    }
  });
  return 0;
}

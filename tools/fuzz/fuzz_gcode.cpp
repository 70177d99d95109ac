// G-code (scene/gcode.h: ParseGcode).
#include "fuzz_common.h"
#include "scene/gcode.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lt::fuzz::ExpectCleanErrors([&] { lt::ParseGcode(std::string_view(reinterpret_cast<const char*>(data), size), "part.gcode"); });
  return 0;
}

// Scene JSON (scene/scene_file.h: ParseSceneText); relative paths resolve in an empty folder.
#include "fuzz_common.h"
#include "scene/scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lt::fuzz::ExpectCleanErrors([&] { lt::ParseSceneText(lt::fuzz::Text(data, size), "scene.json", lt::fuzz::ScratchDir()); });
  return 0;
}

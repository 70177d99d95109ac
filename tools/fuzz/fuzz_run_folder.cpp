// A run folder's text files (pipeline/run_folder_reader.h): manifest.jsonl
// (ReadRunManifest), or, when the bytes start with '{' after a 'R', rig.json
// (ReadRunRig; 'S' for the "sensor" section of scene.json).
#include "fuzz_common.h"
#include "pipeline/run_folder_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path dir = lt::fuzz::ScratchDir() / "run";
  std::filesystem::create_directories(dir);
  for (const char* name : {"manifest.jsonl", "rig.json", "scene.json"}) std::filesystem::remove(dir / name);
  if (size > 0 && (data[0] == 'R' || data[0] == 'S')) {
    const char* name = data[0] == 'R' ? "run/rig.json" : "run/scene.json";
    lt::fuzz::WriteScratch(name, data + 1, size - 1);
    lt::fuzz::ExpectCleanErrors([&] { lt::ReadRunRig(dir); });
  } else {
    lt::fuzz::WriteScratch("run/manifest.jsonl", data, size);
    lt::fuzz::ExpectCleanErrors([&] { lt::ReadRunManifest(dir); });
  }
  return 0;
}

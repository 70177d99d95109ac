// glTF (scene/gltf_loader.h: LoadGltf): .gltf JSON or .glb, told apart by content.
#include "fuzz_common.h"
#include "scene/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = lt::fuzz::WriteScratch("model.gltf", data, size);
  lt::fuzz::ExpectCleanErrors([&] { lt::LoadGltf(path, "model.gltf"); });
  return 0;
}

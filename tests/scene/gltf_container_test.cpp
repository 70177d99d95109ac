// The GLB container as writers in the wild produce it: chunks without the 4-byte
// padding glTF asks for (Blender 2.80's exporter, KhronosGroup/glTF-Blender-IO#628;
// three.js's GLTFExporter before mrdoob/three.js#13395; yocto-gl, fx-gltf), which
// every viewer reads by the chunk lengths.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>

#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;

void AppendU32(std::vector<uint8_t>* out, uint32_t v) {
  uint8_t b[4];
  std::memcpy(b, &v, 4);
  out->insert(out->end(), b, b + 4);
}

// A GLB of `json` and `bin` as they are, without padding (bin empty: no BIN chunk).
std::vector<uint8_t> UnpaddedGlb(const std::string& json, const std::vector<uint8_t>& bin) {
  std::vector<uint8_t> out;
  AppendU32(&out, 0x46546C67);
  AppendU32(&out, 2);
  AppendU32(&out, uint32_t(20 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
  AppendU32(&out, uint32_t(json.size()));
  AppendU32(&out, 0x4E4F534A);
  out.insert(out.end(), json.begin(), json.end());
  if (!bin.empty()) {
    AppendU32(&out, uint32_t(bin.size()));
    AppendU32(&out, 0x004E4942);
    out.insert(out.end(), bin.begin(), bin.end());
  }
  return out;
}

TEST(GltfContainer, ChunksWithoutPaddingAreReadByTheirLengths) {
  TempDir dir;
  // The square with uint8 indices: a BIN payload of 48 + 48 + 6 = 102 bytes.
  GltfBuilder b;
  const int mesh = b.AddTriangleMesh("square", test::SquarePositions(), test::SquareNormals(), {}, {});
  b.json()["meshes"][size_t(mesh)]["primitives"][0]["indices"] = b.AddIndices(test::SquareIndices(), 5121);
  b.AddNode("square_node", mesh);
  std::vector<uint8_t> bin = b.bin();
  ASSERT_NE(bin.size() % 4, 0u);
  nlohmann::json doc = b.json();
  doc["buffers"] = {{{"byteLength", bin.size()}}};
  std::string json = doc.dump();
  if (json.size() % 4 == 0) json += ' ';  // the JSON chunk unpadded too; the BIN header follows at once
  test::WriteBytes(dir / "blender280.glb", UnpaddedGlb(json, bin));

  const GltfAsset a = LoadGltf(dir / "blender280.glb", "blender280.glb");
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].TriangleCount(), 2u);
  EXPECT_EQ(a.meshes[0].positions[2], Eigen::Vector3f(1, 1, 0));
  EXPECT_EQ(a.meshes[0].indices, std::vector<uint32_t>(test::SquareIndices()));
  ASSERT_EQ(a.warnings.size(), 1u);
  EXPECT_EQ(a.warnings[0], "blender280.glb: the GLB's chunks are not padded to 4 bytes as glTF asks (JSON chunk of " +
                               std::to_string(json.size()) + " bytes, BIN chunk of 102 bytes); they are read as their "
                               "lengths say");

  // A BIN chunk that claims more than the file holds is still an error.
  std::vector<uint8_t> glb = UnpaddedGlb(json, bin);
  glb.resize(glb.size() - 5);
  std::memcpy(&glb[8], std::vector<uint8_t>{uint8_t(glb.size()), uint8_t(glb.size() >> 8), 0, 0}.data(), 4);
  test::WriteBytes(dir / "short.glb", glb);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "short.glb", "short.glb"); }),
              HasSubstr("short.glb: invalid GLB: BIN chunk of 102 bytes does not fit in the file"));
}

// glTF allows one BIN chunk, and chunks of unknown types after it (ignored). A
// second BIN chunk (a writer that split its buffers) was ignored silently, its
// data missing from the model: now a warning names the file and the chunk.
TEST(GltfContainer, SecondBinChunkIsWarnedAbout) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  std::vector<uint8_t> glb = b.ToGlb();
  ASSERT_EQ(glb.size() % 4, 0u);
  const size_t second_at = glb.size();
  AppendU32(&glb, 8);
  AppendU32(&glb, 0x004E4942);  // "BIN\0"
  for (int i = 0; i < 8; ++i) glb.push_back(uint8_t(i));
  AppendU32(&glb, 4);
  AppendU32(&glb, 0x41525458);  // "XTRA": an extension's chunk, ignored without a word
  AppendU32(&glb, 0);
  const uint32_t length = uint32_t(glb.size());
  std::memcpy(&glb[8], &length, 4);
  test::WriteBytes(dir / "two_bins.glb", glb);

  const GltfAsset a = LoadGltf(dir / "two_bins.glb", "two_bins.glb");
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].TriangleCount(), 2u);
  ASSERT_EQ(a.warnings.size(), 1u);
  EXPECT_EQ(a.warnings[0], "two_bins.glb: a second BIN chunk (8 bytes at byte " + std::to_string(second_at) +
                               ") ignored: a GLB holds one BIN chunk (buffer 0); only the first is read");
  // Without the second BIN chunk: no warning.
  std::vector<uint8_t> one = b.ToGlb();
  AppendU32(&one, 4);
  AppendU32(&one, 0x41525458);
  AppendU32(&one, 0);
  const uint32_t one_length = uint32_t(one.size());
  std::memcpy(&one[8], &one_length, 4);
  test::WriteBytes(dir / "one_bin.glb", one);
  EXPECT_TRUE(LoadGltf(dir / "one_bin.glb", "one_bin.glb").warnings.empty());
}

}  // namespace
}  // namespace lt

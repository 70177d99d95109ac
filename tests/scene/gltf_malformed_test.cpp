// Malformed glTF files: each is a clean lt::InputError naming the file and the
// place, never a crash or a read out of bounds (the suite also runs under ASan).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <random>

#include "scene/gltf_container.h"
#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;

std::string GlbError(const GltfBuilder& b) {
  TempDir dir;
  b.WriteGlb(dir / "bad.glb");
  return ErrorOf([&] { LoadGltf(dir / "bad.glb", "bad.glb"); });
}

std::string BytesError(const std::vector<uint8_t>& bytes) {
  TempDir dir;
  test::WriteBytes(dir / "bad.glb", bytes);
  return ErrorOf([&] { LoadGltf(dir / "bad.glb", "bad.glb"); });
}

TEST(GltfMalformed, MissingFileNamesThePath) {
  TempDir dir;
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "nope.glb", "nope.glb"); }),
            "nope.glb: file not found (looked for " + (dir / "nope.glb").string() + ")");
}

TEST(GltfMalformed, TruncatedGlb) {
  auto bytes = test::SquareBuilder().ToGlb();
  bytes.resize(bytes.size() - 10);
  EXPECT_THAT(BytesError(bytes), HasSubstr("bad.glb: invalid GLB: truncated: the header says"));
  bytes.resize(15);
  EXPECT_EQ(BytesError(bytes), "bad.glb: invalid GLB: truncated: 15 bytes, the header needs 20");
}

TEST(GltfMalformed, BinChunkLongerThanTheFile) {
  auto bytes = test::SquareBuilder().ToGlb();
  // The BIN chunk header follows the JSON chunk; claim 8 more bytes than there are.
  uint32_t json_length;
  std::memcpy(&json_length, &bytes[12], 4);
  uint32_t bin_length;
  std::memcpy(&bin_length, &bytes[20 + json_length], 4);
  bin_length += 8;
  std::memcpy(&bytes[20 + json_length], &bin_length, 4);
  EXPECT_THAT(BytesError(bytes), HasSubstr("bad.glb: invalid GLB: BIN chunk of"));
}

TEST(GltfMalformed, WrongMagicIsNeitherGlbNorJson) {
  auto bytes = test::SquareBuilder().ToGlb();
  bytes[3] = 'X';
  EXPECT_EQ(BytesError(bytes), "bad.glb: neither a GLB (bad magic: the first bytes are 67 6c 54 58, a GLB starts "
                               "with \"glTF\" = 67 6c 54 46) nor JSON (which starts with '{')");
}

// Embedded buffers are checked before tinygltf: the base64 alphabet and the
// decoded length against byteLength, each error naming /buffers/N/uri.
TEST(GltfMalformed, BadDataUriNamesTheBuffer) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  std::vector<uint8_t> big(300000, 0x55);
  b.AddBufferView(big.data(), big.size());
  auto error_of = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = nlohmann::json::parse(b.ToGltf());
    edit(j);
    test::WriteText(dir / "m.gltf", j.dump());
    return ErrorOf([&] { LoadGltf(dir / "m.gltf", "m.gltf"); });
  };
  auto uri = [](nlohmann::json& j) -> std::string& { return j["buffers"][0]["uri"].get_ref<std::string&>(); };
  const size_t header = std::string("data:application/octet-stream;base64,").size();
  const std::string bad_char = error_of([&](nlohmann::json& j) { uri(j)[header + 200000] = '*'; });
  EXPECT_EQ(bad_char, "m.gltf: /buffers/0/uri: invalid base64 data: '*' at character 200000 of the data");
  const std::string short_data = error_of([&](nlohmann::json& j) { uri(j).resize(uri(j).size() - 8); });
  EXPECT_THAT(short_data, ::testing::MatchesRegex("m\\.gltf: /buffers/0/uri: data URI holds [0-9]+ bytes, "
                                                  "byteLength says [0-9]+"));
  const std::string media = error_of([&](nlohmann::json& j) { uri(j).replace(5, 24, "text/html"); });
  EXPECT_THAT(media, HasSubstr("m.gltf: /buffers/0/uri: a buffer's data URI must start with"));
  EXPECT_LT(media.size(), 300u);
}

// tinygltf quotes whole data URIs in its messages; they are cut short.
TEST(GltfMalformed, DataUrisInMessagesAreShortened) {
  const std::string uri = "data:application/octet-stream;base64," + std::string(100000, 'A');
  EXPECT_EQ(ShortenDataUris("Failed to decode 'uri' : " + uri + " in Buffer\nnext"),
            "Failed to decode 'uri' : " + uri.substr(0, 40) + "... in Buffer\nnext");
  EXPECT_EQ(ShortenDataUris("\"data:,x\" and " + uri), "\"data:,x\" and " + uri.substr(0, 40) + "...");
}

TEST(GltfMalformed, InvalidJson) {
  TempDir dir;
  test::WriteText(dir / "bad.gltf", "{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [}");
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "bad.gltf", "bad.gltf"); }), HasSubstr("bad.gltf:2:"));
}

// tinygltf converts extras recursively: 100 000 nested arrays would overflow its
// stack, so the nesting depth is checked first. Brackets inside strings do not count.
TEST(GltfMalformed, DeeplyNestedJsonIsRefusedBeforeTinygltf) {
  TempDir dir;
  const std::string square = test::SquareBuilder().ToGltf();
  auto with_extras = [&](const std::string& extras) {
    std::string text = square;
    text.insert(text.rfind('}'), ",\"extras\": " + extras);
    test::WriteText(dir / "deep.gltf", text);
  };
  with_extras(std::string(100000, '[') + std::string(100000, ']'));
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "deep.gltf", "deep.gltf"); }),
              ::testing::AllOf(::testing::StartsWith("deep.gltf:"),
                               HasSubstr("invalid glTF: JSON nesting depth exceeds the limit of 256 levels")));
  with_extras(std::string(250, '[') + "\"[[[[[[[[[[{{{{{{{{{{\\\"[[[[[[[[[\"" + std::string(250, ']'));
  EXPECT_EQ(LoadGltf(dir / "deep.gltf", "deep.gltf").instances.size(), 1u);
}

TEST(GltfMalformed, WrongVersion) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["asset"]["version"] = "1.0";
  EXPECT_EQ(GlbError(b), "bad.glb: /asset/version: glTF version must be 2.x, got \"1.0\" (upgrade the file to glTF "
                        "2.0: gltf-pipeline -i in.gltf -o out.gltf does)");
  b.json()["asset"]["version"] = "3.0";
  EXPECT_EQ(GlbError(b), "bad.glb: /asset/version: glTF version must be 2.x, got \"3.0\"");
}

TEST(GltfMalformed, BufferViewOutOfRange) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["bufferViews"][0]["byteOffset"] = 100000;
  EXPECT_THAT(GlbError(b), HasSubstr("bad.glb: /bufferViews/0: byte range [100000, 100048) is outside buffer 0"));
}

TEST(GltfMalformed, AccessorPastItsBufferView) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["accessors"][0]["count"] = 5;  // POSITION: 5 x 12 bytes in a 48-byte view
  EXPECT_EQ(GlbError(b),
            "bad.glb: /accessors/0: 5 elements of 12 bytes (stride 12) from byte 0 do not fit in bufferView 0 (48 bytes)");
  b.json()["accessors"][0]["count"] = 4;
  b.json()["accessors"][0]["byteOffset"] = 4;
  EXPECT_THAT(GlbError(b), HasSubstr("bad.glb: /accessors/0: 4 elements of 12 bytes (stride 12) from byte 4"));
}

TEST(GltfMalformed, StrideSmallerThanElement) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["bufferViews"][0]["byteStride"] = 8;
  EXPECT_THAT(GlbError(b), HasSubstr("bad.glb: /bufferViews/0: byteStride 8 is smaller than an element"));
}

TEST(GltfMalformed, IndexPastTheVertexCount) {
  GltfBuilder b;
  int mesh = b.AddTriangleMesh("m", test::SquarePositions(), {}, {}, {0, 1, 2, 0, 2, 7});
  b.AddNode("n", mesh);
  EXPECT_EQ(GlbError(b), "bad.glb: /accessors/1: index 7 (element 5) is past the vertex count 4");
}

TEST(GltfMalformed, NanPosition) {
  GltfBuilder b;
  std::vector<float> p = test::SquarePositions();
  p[7] = std::nanf("");
  int mesh = b.AddTriangleMesh("m", p, {}, {}, test::SquareIndices());
  b.AddNode("n", mesh);
  EXPECT_EQ(GlbError(b), "bad.glb: /accessors/0: position 2 is not finite (nan)");
}

TEST(GltfMalformed, MissingExternalBufferNamesThePath) {
  TempDir dir;
  test::SquareBuilder().WriteGltf(dir / "m.gltf", false);
  std::filesystem::remove(dir / "m.bin");
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "m.gltf", "m.gltf"); }),
            "m.gltf: /buffers/0/uri: buffer file not found (looked for " + (dir / "m.bin").string() + ")");
}

TEST(GltfMalformed, TruncatedExternalBuffer) {
  TempDir dir;
  test::SquareBuilder().WriteGltf(dir / "m.gltf", false);
  std::filesystem::resize_file(dir / "m.bin", 20);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "m.gltf", "m.gltf"); }),
              HasSubstr("m.gltf: /buffers/0/uri: buffer file " + (dir / "m.bin").string() + " has 20 bytes"));
}

TEST(GltfMalformed, GlbWithoutBinChunk) {
  GltfBuilder b = test::SquareBuilder();
  auto bytes = b.ToGlb();
  uint32_t json_length;
  std::memcpy(&json_length, &bytes[12], 4);
  bytes.resize(20 + json_length);  // drop the BIN chunk, fix the total length
  uint32_t total = uint32_t(bytes.size());
  std::memcpy(&bytes[8], &total, 4);
  // Buffer 0 without a uri is the BIN chunk: its pointer is named (80ef31a; tinygltf's
  // message named none).
  EXPECT_THAT(BytesError(bytes), HasSubstr("bad.glb: /buffers/0/byteLength: 120 bytes, but the GLB has no BIN chunk"));
}

// Chunks of unknown types after JSON and BIN are ignored (glTF 2.0 4.4.3); one
// in the BIN chunk's place is refused naming its type.
TEST(GltfMalformed, GlbChunksOfUnknownTypes) {
  GltfBuilder b = test::SquareBuilder();
  std::vector<uint8_t> bytes = b.ToGlb();
  const std::vector<uint8_t> extra = {8, 0, 0, 0, 'X', 'T', 'R', 'A', 1, 2, 3, 4, 5, 6, 7, 8};
  std::vector<uint8_t> after = bytes;
  after.insert(after.end(), extra.begin(), extra.end());
  uint32_t total = uint32_t(after.size());
  std::memcpy(&after[8], &total, 4);
  TempDir dir;
  test::WriteBytes(dir / "extra.glb", after);
  EXPECT_EQ(LoadGltf(dir / "extra.glb").meshes.at(0).TriangleCount(), 2u);

  uint32_t json_length;
  std::memcpy(&json_length, &bytes[12], 4);
  std::vector<uint8_t> before = bytes;
  before.insert(before.begin() + 20 + json_length, extra.begin(), extra.end());
  std::memcpy(&before[8], &total, 4);
  EXPECT_EQ(BytesError(before),
            "bad.glb: invalid GLB: the second chunk is not BIN but of type 0x41525458 \"XTRA\" (the BIN chunk must "
            "directly follow the JSON chunk; chunks of other types may only come after it)");
}

// Only a GLB's first buffer is the BIN chunk: another buffer without uri has no
// data (tinygltf gave it a copy of the BIN chunk), and a .gltf buffer needs one
// (ToGltf leaves the document's own buffers as they are).
TEST(GltfMalformed, BufferWithoutUri) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["buffers"] = {{{"byteLength", b.bin().size()}}, {{"byteLength", b.bin().size()}}};
  for (auto& view : b.json()["bufferViews"]) view["buffer"] = 1;
  EXPECT_EQ(BytesError(b.ToGlb()),
            "bad.glb: /buffers/1: buffer has no uri (in a GLB only the first buffer, the BIN chunk, may omit it)");
  TempDir dir;
  test::WriteText(dir / "m.gltf", b.ToGltf("m.bin"));
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "m.gltf", "m.gltf"); }),
            "m.gltf: /buffers/0: buffer has no uri (a .gltf buffer needs one)");
}

TEST(GltfMalformed, MissingTextureNamesThePath) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder(true, true);
  b.json()["images"] = {{{"uri", "textures/wood%20grain.png"}}};
  b.json()["textures"] = {{{"source", 0}}};
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("wood", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.WriteGltf(dir / "m.gltf", true);
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "m.gltf", "m.gltf"); }),
            "m.gltf: /images/0/uri: texture image file not found (looked for " +
                (dir / "textures/wood grain.png").string() + ")");
}

TEST(GltfMalformed, ImageBufferViewOutsideItsBuffer) {
  GltfBuilder b = test::SquareBuilder(true, true);
  std::vector<uint8_t> junk(16, 7);
  int view = b.AddBufferView(junk.data(), junk.size());
  b.json()["bufferViews"][size_t(view)]["byteLength"] = 100000;
  b.json()["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}}};
  EXPECT_THAT(GlbError(b), HasSubstr("lies outside buffer 0"));
}

// An image that cannot be decoded is an error only when a texture uses it.
TEST(GltfMalformed, UndecodableImageIsAnErrorOnlyWhenUsed) {
  GltfBuilder b = test::SquareBuilder(true, true);
  std::vector<uint8_t> junk(16, 7);
  int view = b.AddBufferView(junk.data(), junk.size());
  b.json()["images"] = {{{"bufferView", view}, {"mimeType", "image/vnd-ms.dds"}}};
  {
    TempDir dir;
    b.WriteGlb(dir / "unused.glb");
    GltfAsset a = LoadGltf(dir / "unused.glb", "unused.glb");
    EXPECT_EQ(a.instances.size(), 1u);
  }
  b.json()["textures"] = {{{"source", 0}}};
  int mat = b.AddMaterial("painted", {1, 1, 1, 1}, 0, 1);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.json()["meshes"][0]["primitives"][0]["material"] = mat;
  EXPECT_EQ(GlbError(b),
            "bad.glb: /images/0: cannot decode the image: \"image/vnd-ms.dds\" of unknown signature (PNG, JPEG, "
            "BMP, TGA, GIF, PSD, HDR and PNM images are read) (used by texture 0)");
  const char webp[] = "RIFF\x10\0\0\0WEBPVP8 ";
  std::vector<uint8_t> webp_bytes(webp, webp + sizeof webp - 1);
  int webp_view = b.AddBufferView(webp_bytes.data(), webp_bytes.size());
  b.json()["images"][0] = {{"bufferView", webp_view}, {"mimeType", "image/webp"}};
  EXPECT_THAT(GlbError(b), HasSubstr("bad.glb: /images/0: cannot decode the image: WebP (PNG, JPEG"));
  // A texture whose only image is an extension's.
  b.json()["textures"][0] = {{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}};
  EXPECT_EQ(GlbError(b), "bad.glb: /textures/0: texture has no source image that can be read (only an image of "
                         "EXT_texture_webp, which is not supported)");
}

TEST(GltfMalformed, MissingPosition) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
  EXPECT_EQ(GlbError(b), "bad.glb: /meshes/0/primitives/0/attributes: missing required attribute POSITION");
}

TEST(GltfMalformed, PositionWithWrongType) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["accessors"][0]["type"] = "VEC2";
  EXPECT_EQ(GlbError(b), "bad.glb: /accessors/0: type must be VEC3, got VEC2");
}

TEST(GltfMalformed, NormalCountDiffersFromPositions) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["accessors"][1]["count"] = 3;
  EXPECT_EQ(GlbError(b), "bad.glb: /accessors/1: NORMAL has 3 elements, POSITION 4");
}

TEST(GltfMalformed, TriangleListNotAMultipleOfThree) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["accessors"][2]["count"] = 5;
  EXPECT_EQ(GlbError(b), "bad.glb: /meshes/0/primitives/0: a triangle list needs a multiple of 3 vertices, got 5");
}

TEST(GltfMalformed, DanglingReferences) {
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["nodes"][0]["mesh"] = 4;
    EXPECT_EQ(GlbError(b), "bad.glb: /nodes/0/mesh: mesh 4 does not exist (1 meshes)");
  }
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["meshes"][0]["primitives"][0]["material"] = 2;
    EXPECT_EQ(GlbError(b), "bad.glb: /meshes/0/primitives/0/material: material 2 does not exist (0 materials)");
  }
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["nodes"][0]["children"] = {9};
    EXPECT_EQ(GlbError(b), "bad.glb: /nodes/0/children/0: node 9 does not exist (1 nodes)");
  }
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["scene"] = 3;
    EXPECT_EQ(GlbError(b), "bad.glb: /scene: scene 3 does not exist (1 scenes)");
  }
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99;
    EXPECT_EQ(GlbError(b), "bad.glb: /meshes/0/primitives/0/attributes/POSITION: accessor 99 does not exist (3 accessors)");
  }
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["accessors"][0]["bufferView"] = 12;
    EXPECT_THAT(GlbError(b), HasSubstr("bufferView 12 does not exist"));
  }
  {
    // Textures that are not rendered are still references (loaded silently before).
    GltfBuilder b = test::SquareBuilder();
    b.json()["materials"] = {{{"normalTexture", {{"index", 5}}}}};
    EXPECT_EQ(GlbError(b), "bad.glb: /materials/0/normalTexture/index: texture 5 does not exist (0 textures)");
    b.json()["materials"] = {{{"occlusionTexture", {{"index", 0}}}}};
    EXPECT_EQ(GlbError(b), "bad.glb: /materials/0/occlusionTexture/index: texture 0 does not exist (0 textures)");
  }
}

// COLOR_0 of bytes without "normalized": true (glTF allows floats or normalized
// unsigned bytes / shorts) was read as 0..255 and clamped: (0, 128, 0) became
// green 1, (10, 20, 30) white.
TEST(GltfMalformed, VertexColoursOfIntegersThatAreNotNormalized) {
  GltfBuilder b = test::SquareBuilder();
  const std::vector<uint8_t> rgb = {255, 0, 0, 0, 128, 0, 0, 0, 255, 10, 20, 30};
  const int view = b.AddBufferView(rgb.data(), rgb.size());
  b.json()["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = b.AddAccessor(view, 5121, 4, "VEC3", false);
  EXPECT_EQ(GlbError(b), "bad.glb: /accessors/3: COLOR_0 must be floats or normalized unsigned bytes or shorts "
                         "(glTF 3.7.2.1), got componentType 5121 without \"normalized\": true");
  b.json()["accessors"][3]["componentType"] = 5120;  // signed bytes, normalized: not a colour format either
  b.json()["accessors"][3]["normalized"] = true;
  EXPECT_EQ(GlbError(b), "bad.glb: /accessors/3: COLOR_0 must be floats or normalized unsigned bytes or shorts "
                         "(glTF 3.7.2.1), got componentType 5120");
}

TEST(GltfMalformed, NodeCycle) {
  GltfBuilder b = test::SquareBuilder();
  b.AddNode("loop", -1, {}, false);
  b.json()["nodes"][0]["children"] = {1};
  b.json()["nodes"][1]["children"] = {0};
  EXPECT_EQ(GlbError(b), "bad.glb: /nodes/0: node is its own ancestor (the node hierarchy has a cycle)");
}

TEST(GltfMalformed, NonAffineMatrix) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2};
  EXPECT_EQ(GlbError(b), "bad.glb: /nodes/0/matrix: must be affine (last row 0 0 0 1)");
  b.json()["nodes"][0]["matrix"] = {1, 0, 0, 1e-3, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_EQ(GlbError(b), "bad.glb: /nodes/0/matrix: must be affine (last row 0 0 0 1)");
}

// glTF gives a node a matrix or translation / rotation / scale, not both:
// tinygltf read the matrix and dropped the rest, placing the node without its
// translation.
// glTF gives a node a matrix or translation / rotation / scale; tinygltf reads
// the matrix and drops the rest. A node with both is refused where the rest
// would place it differently, and loads where it would not.
TEST(GltfMalformed, MatrixAndTrs) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  b.json()["nodes"][0]["translation"] = {0, 0, 1};
  EXPECT_EQ(GlbError(b), "bad.glb: /nodes/0: has both a matrix and a translation that place it differently (glTF "
                         "gives a node one or the other: a matrix, or translation / rotation / scale)");
  b.json()["nodes"][0].erase("translation");
  b.json()["nodes"][0]["scale"] = {1, 1, 3};
  EXPECT_THAT(GlbError(b), ::testing::HasSubstr("/nodes/0: has both a matrix and a scale that place it differently"));
  // Default values beside the matrix, or values that agree with it: loaded.
  b.json()["nodes"][0]["scale"] = {1, 1, 1};
  b.json()["nodes"][0]["rotation"] = {0, 0, 0, 1};
  EXPECT_EQ(GlbError(b), "");
  const double s = std::sqrt(0.5);  // 90 degrees about z, then 2 up
  b.json()["nodes"][0]["matrix"] = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 2, 1};
  b.json()["nodes"][0]["rotation"] = {0, 0, s, s};
  b.json()["nodes"][0]["translation"] = {0, 0, 2.0000001};
  EXPECT_EQ(GlbError(b), "");
  b.json()["nodes"][0]["rotation"] = {0, 0, -s, s};
  EXPECT_THAT(GlbError(b), ::testing::HasSubstr("/nodes/0: has both a matrix and a translation that place it"));
  b.json()["nodes"][0].erase("scale");
  b.json()["nodes"][0].erase("rotation");
  b.json()["nodes"][0].erase("translation");
  EXPECT_EQ(GlbError(b), "");
}

TEST(GltfMalformed, SparseIndexPastTheCount) {
  GltfBuilder b = test::SquareBuilder();
  std::vector<uint16_t> idx = {9, 0};
  std::vector<float> val = {3, 4, 0};
  int iv = b.AddBufferView(idx.data(), 2);
  int vv = b.AddBufferView(val.data(), 12);
  b.json()["accessors"][0]["sparse"] = {
      {"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", 5123}}}, {"values", {{"bufferView", vv}}}};
  EXPECT_EQ(GlbError(b), "bad.glb: /accessors/0/sparse/indices: index 9 is past the accessor's 4 elements");
}

TEST(GltfMalformed, SparseValuesPastTheirView) {
  GltfBuilder b = test::SquareBuilder();
  std::vector<uint16_t> idx = {1, 2};
  std::vector<float> val = {3, 4, 0};
  int iv = b.AddBufferView(idx.data(), 4);
  int vv = b.AddBufferView(val.data(), 12);
  b.json()["accessors"][0]["sparse"] = {
      {"count", 2}, {"indices", {{"bufferView", iv}, {"componentType", 5123}}}, {"values", {{"bufferView", vv}}}};
  EXPECT_EQ(GlbError(b), "bad.glb: /accessors/0/sparse/values: 2 values do not fit in bufferView 4");
}

// Every truncation of a valid file, and many random byte changes in its JSON,
// give either a loaded asset or an lt::InputError: never another exception or a
// crash (ASan checks the reads).
TEST(GltfMalformed, TruncationsAndMutationsNeverCrash) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder(true, true);
  b.AddMaterial("m", {1, 1, 1, 1}, 0, 1);
  b.json()["meshes"][0]["primitives"][0]["material"] = 0;
  const std::vector<uint8_t> good = b.ToGlb();
  auto attempt = [&](const std::vector<uint8_t>& bytes) {
    test::WriteBytes(dir / "f.glb", bytes);
    try {
      LoadGltf(dir / "f.glb", "f.glb");
    } catch (const InputError&) {
    }
  };
  for (size_t n = 0; n < good.size(); n += 5) {
    attempt(std::vector<uint8_t>(good.begin(), good.begin() + static_cast<ptrdiff_t>(n)));
  }
  uint32_t json_length;
  std::memcpy(&json_length, &good[12], 4);
  std::mt19937 rng(12345);  // fixed seed: the same mutations every run
  const std::string digits = "0123456789-]}\",";
  for (int i = 0; i < 300; ++i) {
    std::vector<uint8_t> bytes = good;
    for (int k = 0; k < 2; ++k) {
      size_t at = 20 + rng() % json_length;
      bytes[at] = uint8_t(digits[rng() % digits.size()]);
    }
    attempt(bytes);
  }
  SUCCEED();
}

}  // namespace
}  // namespace lt

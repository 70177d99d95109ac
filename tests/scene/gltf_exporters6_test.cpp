// Features found in the sixth pass over exporters (docs/scene-format.md, "Real files
// checked, sixth pass") and the last pass's left-overs: data: URIs in RFC 2397's
// percent-encoded form or with media-type parameters, and the materials no
// triangle takes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/base64.h"
#include "core/image_io.h"
#include "scene/gltf_loader.h"
#include "scene/scene_file.h"
#include "scene/scene_geometry.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;

// The bytes of a 1x1 PNG of the given RGBA texel.
std::vector<uint8_t> PngBytes(const TempDir& dir, uint8_t r, uint8_t g, uint8_t b) {
  Image<uint8_t> texel(1, 1, 4, 255);
  texel.At(0, 0, 0) = r;
  texel.At(0, 0, 1) = g;
  texel.At(0, 0, 2) = b;
  WriteImage(dir / "texel.png", texel);
  std::ifstream in(dir / "texel.png", std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// RFC 3986 percent-encoding of every byte but unreserved ASCII, as
// encodeURIComponent and Python's urllib.parse.quote(safe="") write it.
std::string PercentEncoded(const std::vector<uint8_t>& bytes) {
  static const char* kHex = "0123456789ABCDEF";
  std::string s;
  for (uint8_t c : bytes) {
    if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
        c == '.' || c == '~') {
      s += char(c);
    } else {
      s += '%';
      s += kHex[c >> 4];
      s += kHex[c & 15];
    }
  }
  return s;
}

// A textured square whose image 0 is `image_uri`, its buffer embedded as base64.
GltfBuilder TexturedSquare(const std::string& image_uri) {
  GltfBuilder b = test::SquareBuilder(true, true);
  const int mat = b.AddMaterial("painted", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.json()["meshes"][0]["primitives"][0]["material"] = mat;
  b.json()["textures"] = {{{"source", 0}}};
  b.json()["images"] = {{{"uri", image_uri}}};
  return b;
}

// glTF's image URIs are RFC 2397 data: URIs, whose data may be percent-encoded
// octets instead of base64 (`data:image/png,%89PNG%0D%0A...`, `data:image/svg+xml;
// charset=utf-8,%3Csvg...`, as browsers' encodeURIComponent writes them). tinygltf
// took such a URI for a file name: the file was refused, '/images/0: image could not
// be loaded from "data:image/png,%89PNG%0D%0A..."'. Now the data is decoded as
// browsers decode it, then decoded by its content like any image: a PNG reads, an SVG
// gets the undecodable-image error naming /images/0. A data: URI without its comma
// is an error naming its uri.
TEST(GltfExporters6, PercentEncodedImageDataUrisAreRead) {
  TempDir dir;
  const std::vector<uint8_t> png = PngBytes(dir, 255, 0, 0);
  for (const std::string header : {"data:image/png,", "data:image/png;charset=utf-8,", "DATA:,"}) {
    SCOPED_TRACE(header);
    TexturedSquare(header + PercentEncoded(png)).WriteGltf(dir / "pct.gltf", true);
    const GltfAsset a = LoadGltf(dir / "pct.gltf", "pct.gltf");
    ASSERT_EQ(a.materials.size(), 1u);
    ASSERT_NE(a.materials[0].base_color_texture, nullptr);
    EXPECT_EQ(a.materials[0].base_color_texture->Texel(0, 0), Eigen::Vector4f(1, 0, 0, 1));
    EXPECT_TRUE(a.warnings.empty()) << test::AllWarnings(a);
  }
  // Unreserved characters written as themselves, and a '%' not followed by two hex
  // digits standing for itself, as browsers read it: the bytes "A%zB" and "%4".
  {
    const std::string text = "A%zB%4";
    TexturedSquare("data:text/plain," + text).WriteGltf(dir / "text.gltf", true);
    EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "text.gltf", "text.gltf"); }),
              "text.gltf: /images/0: cannot decode the image: an unknown format (PNG, JPEG, BMP, TGA, GIF, PSD, HDR and "
              "PNM images are read) (used by texture 0)");
  }
  TexturedSquare("data:image/svg+xml;charset=utf-8,%3Csvg%20xmlns%3D%22http%3A%2F%2Fwww.w3.org%2F2000%2Fsvg%22%2F%3E")
      .WriteGltf(dir / "svg.gltf", true);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "svg.gltf", "svg.gltf"); }),
              HasSubstr("svg.gltf: /images/0: cannot decode the image: "));
  TexturedSquare("data:image/png").WriteGltf(dir / "nocomma.gltf", true);
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "nocomma.gltf", "nocomma.gltf"); }),
            "nocomma.gltf: /images/0/uri: a data: URI needs a ',' between its header and its data, got "
            "\"data:image/png\"");
}

// glTF embeds buffers as base64 data: URIs of application/octet-stream or
// application/gltf-buffer. A media type with parameters (`;charset=binary`: RFC
// 2397's mediatype holds them, glTF-Validator reads the type without them) is read;
// it was refused ('a buffer's data URI must start with ...'). Percent-encoded data
// stays an error, now saying what is wrong.
TEST(GltfExporters6, BufferDataUrisWithParametersAreReadPercentEncodedOnesNamed) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.WriteGltf(dir / "plain.gltf", true);
  const GltfAsset plain = LoadGltf(dir / "plain.gltf");
  const std::string data = Base64Encode(b.bin().data(), b.bin().size());
  for (const std::string header : {"data:application/octet-stream;charset=binary;base64,",
                                   "data:Application/GLTF-Buffer;name=part.bin;base64,"}) {
    SCOPED_TRACE(header);
    nlohmann::json doc = nlohmann::json::parse(b.ToGltf());
    doc["buffers"][0]["uri"] = header + data;
    test::WriteText(dir / "params.gltf", doc.dump());
    const GltfAsset a = LoadGltf(dir / "params.gltf", "params.gltf");
    ASSERT_EQ(a.meshes.size(), 1u);
    EXPECT_EQ(a.meshes[0].positions, plain.meshes[0].positions);
  }
  nlohmann::json doc = nlohmann::json::parse(b.ToGltf());
  doc["buffers"][0]["uri"] = "data:application/octet-stream," + PercentEncoded(b.bin());
  test::WriteText(dir / "pct.gltf", doc.dump());
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "pct.gltf", "pct.gltf"); }),
              HasSubstr("pct.gltf: /buffers/0/uri: a buffer's data URI must hold base64 (\";base64,\" before the "
                        "data, as glTF embeds buffers), got \"data:application/octet-stream,%00%00%00%..."));
  // Another media type is refused as before.
  doc["buffers"][0]["uri"] = "data:text/plain;charset=utf-8;base64," + data;
  test::WriteText(dir / "text.gltf", doc.dump());
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "text.gltf", "text.gltf"); }),
              HasSubstr("text.gltf: /buffers/0/uri: a buffer's data URI must start with "));
}

// glTF 1.0, as JSON or as its binary container (KHR_binary_glTF: version 1, a
// 20-byte header of content length and format, then the JSON), is refused with how
// to upgrade it. Before, the GLB said 'container version 1, only 2 is supported'
// and the JSON 'glTF version must be 2.x, got "1.0"', neither saying what to do.
TEST(GltfExporters6, Gltf1FilesAreRefusedWithTheUpgrade) {
  TempDir dir;
  const std::string json = R"({"asset": {"version": "1.0"}, "extensionsUsed": ["KHR_binary_glTF"]})";
  std::vector<uint8_t> glb = {'g', 'l', 'T', 'F'};
  for (uint32_t word : {1u, uint32_t(20 + json.size()), uint32_t(json.size()), 0u}) {
    for (int k = 0; k < 4; ++k) glb.push_back(uint8_t(word >> (8 * k)));
  }
  glb.insert(glb.end(), json.begin(), json.end());
  test::WriteBytes(dir / "v1.glb", glb);
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "v1.glb", "v1.glb"); }),
            "v1.glb: invalid GLB: container version 1 (glTF 1.0's KHR_binary_glTF), only 2 is supported: upgrade the "
            "file to glTF 2.0 (gltf-pipeline -i in.glb -o out.glb does)");
  test::WriteText(dir / "v1.gltf", json);
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "v1.gltf", "v1.gltf"); }),
            "v1.gltf: /asset/version: glTF version must be 2.x, got \"1.0\" (upgrade the file to glTF 2.0: "
            "gltf-pipeline -i in.gltf -o out.gltf does)");
}

// A GLB's buffer 0 without a uri is its BIN chunk: a byteLength past the chunk
// (a writer that counted the buffer before trimming it, a truncated chunk) is an
// error naming /buffers/0/byteLength. Before, tinygltf's message named no place
// ("invalid glTF: Invalid `byteLength'. Must be equal or less than binary size").
TEST(GltfExporters6, GlbBufferLongerThanItsBinChunkIsNamed) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  const size_t bin = b.bin().size();
  b.WriteGlb(dir / "ok.glb");
  EXPECT_EQ(LoadGltf(dir / "ok.glb").instances.size(), 1u);
  std::vector<uint8_t> glb = b.ToGlb();
  // The JSON chunk: rewrite byteLength, keep the chunk's length by padding with spaces.
  const uint32_t json_length = uint32_t(glb[12]) | uint32_t(glb[13]) << 8 | uint32_t(glb[14]) << 16 | uint32_t(glb[15]) << 24;
  std::string json(glb.begin() + 20, glb.begin() + 20 + json_length);
  const std::string from = "\"byteLength\":" + std::to_string(bin) + "}";
  const size_t at = json.find(from);
  ASSERT_NE(at, std::string::npos) << json;
  const std::string to = "\"byteLength\":" + std::to_string(bin + 64) + "}";
  ASSERT_LE(to.size(), from.size() + 2);
  json.replace(at, from.size(), to);
  json.resize(json_length, ' ');
  std::copy(json.begin(), json.end(), glb.begin() + 20);
  test::WriteBytes(dir / "long.glb", glb);
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "long.glb", "long.glb"); }),
            "long.glb: /buffers/0/byteLength: " + std::to_string(bin + 64) + " bytes, but the GLB's BIN chunk holds " +
                std::to_string(bin) + " (buffer 0 without a uri is the BIN chunk; a truncated or mis-written file?)");
}

// SceneGeometry::UsedMaterials, which `lasertwin info` marks: a glTF material no
// placed triangle names (a library material, one of a mesh no node places, one of
// lines) and a scene material no object takes are unused; the printed part's and
// an object's own material are used.
TEST(GltfExporters6, MaterialsNoTriangleTakesAreFound) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  const int used = b.AddMaterial("used", {0.5, 0.5, 0.5, 1}, 0, 0.5);
  const int library = b.AddMaterial("library", {0.5, 0.5, 0.5, 1}, 1, 0.5);
  const int unplaced = b.AddMaterial("unplaced", {0.5, 0.5, 0.5, 1}, 0, 0.5);
  const int lines = b.AddMaterial("lines", {0, 0, 0, 1}, 0, 0.5);
  b.json()["meshes"][0]["primitives"][0]["material"] = used;
  nlohmann::json outline = b.json()["meshes"][0]["primitives"][0];
  outline["mode"] = 1;
  outline["material"] = lines;
  b.json()["meshes"][0]["primitives"].push_back(outline);
  b.AddTriangleMesh("spare", test::SquarePositions(), test::SquareNormals(), {}, test::SquareIndices(), unplaced);
  (void)library;
  b.WriteGltf(dir / "part.gltf", true);
  test::SquareBuilder().WriteGltf(dir / "other.gltf", true);
  test::WriteText(dir / "scene.json", R"({"objects": [{"name": "a", "gltf": "part.gltf"},
      {"name": "b", "gltf": "other.gltf", "material": "pla"}],
    "materials": {"pla": {"base_color": [0.8, 0.8, 0.8]}, "steel": {"metallic": 1}},
    "sensor": {"camera": {"resolution": [8, 8], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}}})");
  const SceneGeometry g = LoadSceneGeometry(LoadSceneFile(dir / "scene.json"));
  std::vector<std::string> names;
  for (const Material& m : g.materials) names.push_back(m.name);
  ASSERT_EQ(names, (std::vector<std::string>{"pla", "steel", "used", "library", "unplaced", "lines"}));
  EXPECT_EQ(g.UsedMaterials(), (std::vector<bool>{true, false, true, false, false, false}));
}

}  // namespace
}  // namespace lt

// Features found in the fifth pass over real files (docs/scene-format.md, "Real
// files checked, fifth pass"): base64 data: URIs wrapped into lines or with an
// upper-case header, and materials
// written as WebGL shaders (COLLADA2GLTF -t) or KHR_materials_common.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/base64.h"
#include "core/image_io.h"
#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;

// `data` as base64 wrapped into lines of `width` characters ending in `eol`, as
// Python's base64.encodebytes (76, "\n"), MIME encoders (76, "\r\n") and OpenSSL
// (64, "\n") write it.
std::string Wrapped(const std::vector<uint8_t>& data, size_t width, const std::string& eol) {
  const std::string b64 = Base64Encode(data.data(), data.size());
  std::string s;
  for (size_t i = 0; i < b64.size(); i += width) s += b64.substr(i, width) + eol;
  return s;
}

// A data: URI's base64 wrapped into lines (a script's json.dump of
// base64.encodebytes, which escapes each line end as "\n") is read as browsers read
// it (the base64 of a data: URL is decoded forgivingly, ASCII whitespace skipped):
// the buffer and the image load as unwrapped. Before, the buffer was refused
// ('/buffers/0/uri: invalid base64 data: byte 10 at character 76 of the data') and
// the image was 'a corrupt PNG'. Other characters outside base64 are still errors.
TEST(GltfExporters5, Base64WrappedIntoLinesIsRead) {
  TempDir dir;
  Image<uint8_t> texel(1, 1, 4, 0);
  texel.At(0, 0, 0) = 255;  // red
  texel.At(0, 0, 3) = 255;
  WriteImage(dir / "red.png", texel);
  std::ifstream in(dir / "red.png", std::ios::binary);
  const std::vector<uint8_t> png_bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(png_bytes.empty());

  GltfBuilder b = test::SquareBuilder(true, true);
  const int mat = b.AddMaterial("painted", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.json()["meshes"][0]["primitives"][0]["material"] = mat;
  b.json()["textures"] = {{{"source", 0}}};
  const GltfAsset plain = [&] {
    b.json()["images"] = {{{"uri", "data:image/png;base64," + Base64Encode(png_bytes.data(), png_bytes.size())}}};
    b.WriteGltf(dir / "plain.gltf", true);
    return LoadGltf(dir / "plain.gltf", "plain.gltf");
  }();
  for (const auto& [width, eol] : std::vector<std::pair<size_t, std::string>>{{76, "\n"}, {76, "\r\n"}, {64, "\n"}}) {
    SCOPED_TRACE(width);
    b.json()["images"] = {{{"uri", "data:image/png;base64," + Wrapped(png_bytes, width, eol)}}};
    nlohmann::json doc = nlohmann::json::parse(b.ToGltf());
    std::string& uri = doc["buffers"][0]["uri"].get_ref<std::string&>();
    uri = "data:application/octet-stream;base64," + Wrapped(b.bin(), width, eol);
    ASSERT_NE(uri.find('\n'), std::string::npos);
    test::WriteText(dir / "wrapped.gltf", doc.dump());
    const GltfAsset a = LoadGltf(dir / "wrapped.gltf", "wrapped.gltf");
    ASSERT_EQ(a.meshes.size(), 1u);
    EXPECT_EQ(a.meshes[0].positions, plain.meshes[0].positions);
    EXPECT_EQ(a.meshes[0].texcoords, plain.meshes[0].texcoords);
    ASSERT_NE(a.materials[0].base_color_texture, nullptr);
    EXPECT_EQ(a.materials[0].base_color_texture->Texel(0, 0), Eigen::Vector4f(1, 0, 0, 1));
    EXPECT_TRUE(a.warnings.empty()) << test::AllWarnings(a);
  }
  // A character that is neither base64 nor whitespace is named as before, at its
  // place in the data as written (a line end, 76 characters, a line end).
  nlohmann::json doc = nlohmann::json::parse(b.ToGltf());
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64,\n" + Wrapped(b.bin(), 76, "\n*");
  test::WriteText(dir / "bad.gltf", doc.dump());
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "bad.gltf", "bad.gltf"); }),
              HasSubstr("bad.gltf: /buffers/0/uri: invalid base64 data: '*' at character 78 of the data"));
}


// URI schemes and media types are case-insensitive (RFC 3986, RFC 2045), and
// browsers read `DATA:...;BASE64,`; tinygltf reads only lower case. Such a buffer
// was refused as a remote file ('... is a data: URI; only local files are read
// (download it ...)'); now headers in any case are read, with an image's
// media-type relabelling (image/jpg) after them.
TEST(GltfExporters5, UpperCaseDataUriHeadersAreRead) {
  TempDir dir;
  Image<uint8_t> texel(1, 1, 4, 0);
  texel.At(0, 0, 1) = 255;  // green
  texel.At(0, 0, 3) = 255;
  WriteImage(dir / "green.png", texel);
  std::ifstream in(dir / "green.png", std::ios::binary);
  const std::vector<uint8_t> png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  GltfBuilder b = test::SquareBuilder(true, true);
  const int mat = b.AddMaterial("painted", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.json()["meshes"][0]["primitives"][0]["material"] = mat;
  b.json()["textures"] = {{{"source", 0}}};
  b.json()["images"] = {{{"uri", "data:image/png;base64," + Base64Encode(png.data(), png.size())}}};
  b.WriteGltf(dir / "plain.gltf", true);
  for (const std::string image_header : {"DATA:IMAGE/PNG;BASE64,", "Data:image/JPG;Base64,"}) {
    SCOPED_TRACE(image_header);
    b.json()["images"] = {{{"uri", image_header + Base64Encode(png.data(), png.size())}}};
    nlohmann::json doc = nlohmann::json::parse(b.ToGltf());
    doc["buffers"][0]["uri"] = "DATA:Application/Octet-Stream;BASE64," + Base64Encode(b.bin().data(), b.bin().size());
    test::WriteText(dir / "upper.gltf", doc.dump());
    const GltfAsset a = LoadGltf(dir / "upper.gltf", "upper.gltf");
    ASSERT_EQ(a.meshes.size(), 1u);
    EXPECT_EQ(a.meshes[0].positions, LoadGltf(dir / "plain.gltf").meshes[0].positions);
    ASSERT_NE(a.materials[0].base_color_texture, nullptr);
    EXPECT_EQ(a.materials[0].base_color_texture->Texel(0, 0), Eigen::Vector4f(0, 1, 0, 1));
  }
}

// Khronos' Box glTF-techniqueWebGL (COLLADA2GLTF -t, a glTF 2.0 draft) requires
// KHR_technique_webgl: its materials are shader programs (`technique`, `values`,
// top-level `techniques`, `programs`, `shaders`); KHR_techniques_webgl is the
// extension's later form. They concern only the materials, so a file loaded
// without them (every object with its own "material") is accepted; with them the
// refusal says what to do, as it does for KHR_materials_common. Before, both
// were refused naming the extension alone, whatever the object's material.
TEST(GltfExporters5, ShaderMaterialsAreReplacedByTheObjectsMaterial) {
  TempDir dir;
  GltfLoadOptions geometry_only;
  geometry_only.materials = false;
  const std::string shaders = "the materials are WebGL shader programs: give the object its own \"material\", which "
                              "replaces them";
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["materials"] = {{{"values", {{"diffuse", {0.8, 0, 0, 1}}}}, {"technique", 0}}};
    b.json()["meshes"][0]["primitives"][0]["material"] = 0;
    b.json()["techniques"] = {{{"program", 0}}};
    b.json()["programs"] = {{{"fragmentShader", 1}, {"vertexShader", 0}}};
    b.json()["shaders"] = {{{"type", 35633}, {"uri", "Box0.vert"}}, {{"type", 35632}, {"uri", "Box1.frag"}}};
    b.json()["extensionsUsed"] = {"KHR_technique_webgl"};
    b.json()["extensionsRequired"] = {"KHR_technique_webgl"};
    b.WriteGltf(dir / "draft.gltf", true);
    EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "draft.gltf", "draft.gltf"); }),
              "draft.gltf: /extensionsRequired/0: required extension \"KHR_technique_webgl\" is not supported (" +
                  shaders + ")");
    const GltfAsset a = LoadGltf(dir / "draft.gltf", "draft.gltf", geometry_only);
    ASSERT_EQ(a.instances.size(), 1u);
    EXPECT_EQ(a.meshes[0].TriangleCount(), 2u);
    EXPECT_TRUE(a.warnings.empty()) << test::AllWarnings(a);
  }
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["materials"] = {{{"extensions", {{"KHR_techniques_webgl", {{"technique", 0}}}}}}};
    b.json()["meshes"][0]["primitives"][0]["material"] = 0;
    b.json()["extensions"]["KHR_techniques_webgl"] = {{"techniques", {{{"program", 0}}}}};
    b.json()["extensionsUsed"] = {"KHR_techniques_webgl"};
    b.json()["extensionsRequired"] = {"KHR_techniques_webgl"};
    b.WriteGltf(dir / "techniques.gltf", true);
    EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "techniques.gltf", "techniques.gltf"); }), HasSubstr(shaders));
    EXPECT_EQ(LoadGltf(dir / "techniques.gltf", "techniques.gltf", geometry_only).instances.size(), 1u);
  }
  {
    GltfBuilder b = test::SquareBuilder();
    b.json()["materials"] = {
        {{"extensions", {{"KHR_materials_common", {{"technique", "PHONG"}, {"values", {{"diffuse", {1, 0, 0, 1}}}}}}}}}};
    b.json()["meshes"][0]["primitives"][0]["material"] = 0;
    b.json()["extensionsUsed"] = {"KHR_materials_common"};
    b.json()["extensionsRequired"] = {"KHR_materials_common"};
    b.WriteGltf(dir / "common.gltf", true);
    EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "common.gltf", "common.gltf"); }),
                HasSubstr("required extension \"KHR_materials_common\" is not supported (the materials are glTF 1.0's "
                          "Blinn, Phong, Lambert or constant shading: give the object its own \"material\""));
    EXPECT_EQ(LoadGltf(dir / "common.gltf", "common.gltf", geometry_only).instances.size(), 1u);
  }
}

}  // namespace
}  // namespace lt

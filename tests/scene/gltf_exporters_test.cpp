// glTF features that other exporters write and that the basic loader tests do not
// cover: a texture on a second UV set (Blender, Sketchfab), EXT_mesh_gpu_instancing
// (gltfpack -mi, CAD assemblies), morph targets posed by their default weights
// (Blender shape keys), a node with several parents, and a file in millimetres.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/image_io.h"
#include "scene/gltf_loader.h"
#include "scene/scene_file.h"
#include "scene/scene_geometry.h"
#include "test_util.h"

namespace lt {
namespace {

using test::AllWarnings;
using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;
using ::testing::Not;

GltfAsset LoadGlb(const GltfBuilder& b, const TempDir& dir, const std::string& stem = "model") {
  b.WriteGlb(dir / (stem + ".glb"));
  return LoadGltf(dir / (stem + ".glb"), stem + ".glb");
}

// ------------------------------------------------------------------ TEXCOORD_n

// The square with TEXCOORD_0 all at (0.9, 0.9) and the square's own coordinates
// in TEXCOORD_1, and a material whose base-colour texture (a 1x1 PNG) reads texCoord 1.
GltfBuilder SquareWithSecondUvSet(const TempDir& dir) {
  GltfBuilder b = test::SquareBuilder(true, false);
  auto& attributes = b.json()["meshes"][0]["primitives"][0]["attributes"];
  attributes["TEXCOORD_0"] = b.AddFloats(std::vector<float>(8, 0.9f), "VEC2");
  attributes["TEXCOORD_1"] = b.AddFloats(test::SquareTexcoords(), "VEC2");
  WriteImage(dir / "tex.png", Image<uint8_t>(1, 1, 4, 255));
  b.json()["images"] = {{{"uri", "tex.png"}}};
  b.json()["textures"] = {{{"source", 0}}};
  int mat = b.AddMaterial("second_uv", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}, {"texCoord", 1}};
  b.json()["meshes"][0]["primitives"][0]["material"] = mat;
  return b;
}

std::vector<float> Flatten(const std::vector<Eigen::Vector2f>& uv) {
  std::vector<float> out;
  for (const auto& t : uv) out.insert(out.end(), {t.x(), t.y()});
  return out;
}

TEST(GltfExporters, TextureOnASecondUvSetReadsThatSet) {
  TempDir dir;
  GltfBuilder b = SquareWithSecondUvSet(dir);
  b.WriteGltf(dir / "model.gltf", false);
  GltfAsset a = LoadGltf(dir / "model.gltf");
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(Flatten(a.meshes[0].texcoords), test::SquareTexcoords());
  EXPECT_EQ(a.materials[0].base_color_texcoord, 1);
  EXPECT_TRUE(a.warnings.empty()) << AllWarnings(a);

  // KHR_texture_transform's texCoord overrides the textureInfo's.
  auto& info = b.json()["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"];
  info["texCoord"] = 0;
  info["extensions"]["KHR_texture_transform"] = {{"texCoord", 1}};
  b.WriteGltf(dir / "model.gltf", false);
  EXPECT_EQ(Flatten(LoadGltf(dir / "model.gltf").meshes[0].texcoords), test::SquareTexcoords());

  // A primitive without the set its texture reads falls back to TEXCOORD_0, with a warning.
  info["extensions"]["KHR_texture_transform"] = {{"texCoord", 2}};
  b.WriteGltf(dir / "model.gltf", false);
  GltfAsset a2 = LoadGltf(dir / "model.gltf");
  EXPECT_EQ(Flatten(a2.meshes[0].texcoords), std::vector<float>(8, 0.9f));
  EXPECT_THAT(AllWarnings(a2), HasSubstr("mesh \"square\" primitive 0: material \"second_uv\" reads TEXCOORD_2, "
                                         "which the primitive does not have; TEXCOORD_0 is used"));
}

// Two primitives of one mesh whose materials read different sets each keep their own.
TEST(GltfExporters, EachPrimitiveReadsTheSetOfItsMaterial) {
  TempDir dir;
  GltfBuilder b = SquareWithSecondUvSet(dir);
  b.json()["meshes"][0]["primitives"].push_back(b.json()["meshes"][0]["primitives"][0]);
  b.json()["meshes"][0]["primitives"][1]["material"] = b.AddMaterial("first_uv", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.WriteGltf(dir / "model.gltf", false);
  GltfAsset a = LoadGltf(dir / "model.gltf");
  ASSERT_EQ(a.meshes.size(), 1u);
  const Mesh& m = a.meshes[0];
  ASSERT_EQ(m.TriangleCount(), 4u);
  for (size_t t = 0; t < 4; ++t) {
    const bool second = m.triangle_material[t] == 0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2f uv = m.texcoords[m.indices[3 * t + size_t(k)]];
      if (second) {
        EXPECT_TRUE(uv.x() == 0 || uv.x() == 1) << t;
      } else {
        EXPECT_EQ(uv, Eigen::Vector2f(0.9f, 0.9f)) << t;
      }
    }
  }
}

// ------------------------------------------------------------------ EXT_mesh_gpu_instancing

TEST(GltfExporters, GpuInstancingPlacesEveryInstance) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.json()["nodes"][0]["translation"] = {0, 0, 1};
  const double s = std::sqrt(0.5);
  const int t = b.AddFloats({1, 0, 0, 0, 2, 0}, "VEC3");
  const int r = b.AddFloats({0, 0, 0, 1, 0, 0, float(s), float(s)}, "VEC4");  // identity, 90 deg about z
  const int sc = b.AddFloats({1, 1, 1, 2, 2, 2}, "VEC3");
  b.json()["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"] = {
      {"attributes", {{"TRANSLATION", t}, {"ROTATION", r}, {"SCALE", sc}}}};
  b.json()["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  b.json()["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  GltfAsset a = LoadGlb(b, dir);
  EXPECT_TRUE(a.warnings.empty()) << AllWarnings(a);
  ASSERT_EQ(a.meshes.size(), 1u);
  ASSERT_EQ(a.instances.size(), 2u);
  // node * instance: corner (1, 0, 0) of the square goes to (2, 0, 1) and (0, 4, 1) + (0, 0, 0).
  EXPECT_TRUE((a.instances[0].file_from_mesh * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(2, 0, 1), 1e-6));
  EXPECT_TRUE((a.instances[1].file_from_mesh * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(0, 4, 1), 1e-6));
  EXPECT_EQ(a.instances[1].node_name, "square_node/instance 1");

  // The attributes must agree on the instance count.
  b.json()["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] =
      b.AddFloats({1, 1, 1}, "VEC3");
  EXPECT_THAT(ErrorOf([&] { LoadGlb(b, dir); }),
              HasSubstr("model.glb: /nodes/0/extensions/EXT_mesh_gpu_instancing/attributes/SCALE: 1 elements, "
                        "TRANSLATION has 2"));
}

// Older Sketchfab and 3ds Max exports require the specular-glossiness extension,
// which is converted (gltf_loader_test.cpp), so the file is not refused.
TEST(GltfExporters, RequiredSpecularGlossinessIsConverted) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("old", {1, 1, 1, 1}, 1, 1);
  b.json()["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"] = {
      {"diffuseFactor", {0.5, 0.25, 0.125, 1}}, {"glossinessFactor", 0.75}};
  b.json()["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness"};
  b.json()["extensionsRequired"] = {"KHR_materials_pbrSpecularGlossiness"};
  GltfAsset a = LoadGlb(b, dir);
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_EQ(a.materials[0].base_color, Eigen::Vector3f(0.5f, 0.25f, 0.125f));
  EXPECT_FLOAT_EQ(a.materials[0].roughness, 0.25f);
}

// KHR_materials_transmission (Blender's glass and clear plastics): glTF's
// dielectric is mix(diffuse, transmission, transmissionFactor); transmitted light
// is not traced, but the diffuse share goes, so a clear part shows no bright
// diffuse stripe. A metal has no transmission.
TEST(GltfExporters, TransmissionTakesItsShareFromTheDiffuseLayer) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("clear", {0.8, 0.4, 0.2, 1}, 0, 0.1);
  b.AddMaterial("metal", {0.8, 0.4, 0.2, 1}, 1, 0.1);
  b.AddMaterial("half", {0.8, 0.4, 0.2, 1}, 0.5, 0.1);
  for (int m = 0; m < 3; ++m) b.json()["materials"][m]["extensions"]["KHR_materials_transmission"] = {{"transmissionFactor", 0.75}};
  for (int m = 1; m < 3; ++m) {  // each used by a triangle (unused materials are not read: GltfUnused)
    b.json()["meshes"][0]["primitives"].push_back(b.json()["meshes"][0]["primitives"][0]);
    b.json()["meshes"][0]["primitives"][size_t(m)]["material"] = m;
  }
  b.json()["extensionsUsed"] = {"KHR_materials_transmission"};
  GltfAsset a = LoadGlb(b, dir);
  ASSERT_EQ(a.materials.size(), 3u);
  EXPECT_TRUE(a.materials[0].base_color.isApprox(Eigen::Vector3f(0.2f, 0.1f, 0.05f)));    // x (1 - 0.75)
  EXPECT_TRUE(a.materials[1].base_color.isApprox(Eigen::Vector3f(0.8f, 0.4f, 0.2f)));     // metal: unchanged
  EXPECT_TRUE(a.materials[2].base_color.isApprox(Eigen::Vector3f(0.5f, 0.25f, 0.125f)));  // x (1 - 0.75 * 0.5)
  EXPECT_THAT(AllWarnings(a), HasSubstr("materials \"clear\", \"metal\", \"half\""));

  // Outside [0, 1]: clamped, as every factor is (GltfExporters4), and named.
  b.json()["materials"][0]["extensions"]["KHR_materials_transmission"]["transmissionFactor"] = 2;
  const GltfAsset clamped = LoadGlb(b, dir);
  EXPECT_EQ(clamped.materials[0].base_color, Eigen::Vector3f::Zero());
  EXPECT_THAT(AllWarnings(clamped), HasSubstr("/materials/0/extensions/KHR_materials_transmission/transmissionFactor 2"));
}

// KHR_materials_unlit, as the Khronos UnlitTest writes it (required, base colour
// only) and photogrammetry exports use it: the part is a diffuse surface of its base
// colour. UnlitTest was refused ('required extension "KHR_materials_unlit" is not
// supported'); optional, its materials (no metallicFactor) loaded as metals.
TEST(GltfExporters, UnlitMaterialsAreDiffuseSurfacesOfTheirBaseColour) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("Orange", {1, 0.217637640824031, 0, 1}, 1, 1);
  b.AddMaterial("lit", {0.5, 0.5, 0.5, 1}, 1, 0.25);
  b.json()["materials"][0]["pbrMetallicRoughness"].erase("metallicFactor");
  b.json()["materials"][0]["pbrMetallicRoughness"].erase("roughnessFactor");
  b.json()["materials"][0]["emissiveFactor"] = {1, 1, 1};
  b.json()["materials"][0]["extensions"]["KHR_materials_unlit"] = nlohmann::json::object();
  b.json()["extensionsUsed"] = {"KHR_materials_unlit"};
  b.json()["extensionsRequired"] = {"KHR_materials_unlit"};
  GltfAsset a = LoadGlb(b, dir);
  ASSERT_EQ(a.materials.size(), 2u);
  EXPECT_TRUE(a.materials[0].base_color.isApprox(Eigen::Vector3f(1, 0.217637640824031f, 0)));
  EXPECT_EQ(a.materials[0].metallic, 0.0f);
  EXPECT_EQ(a.materials[0].roughness, 1.0f);
  EXPECT_EQ(a.materials[0].emissive, Eigen::Vector3f::Zero());
  EXPECT_EQ(a.materials[1].metallic, 1.0f);  // a material without the extension keeps its values
  EXPECT_FLOAT_EQ(a.materials[1].roughness, 0.25f);
  EXPECT_THAT(AllWarnings(a), HasSubstr("model.glb: KHR_materials_unlit: read as a diffuse surface of the base colour "
                                        "(metallic 0, roughness 1, no emission; the other properties are the "
                                        "extension's fallbacks), material \"Orange\""));
}

// ------------------------------------------------------------------ morph targets

TEST(GltfExporters, MorphTargetsArePosedByTheirDefaultWeights) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  auto& prim = b.json()["meshes"][0]["primitives"][0];
  prim["targets"] = {{{"POSITION", b.AddFloats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3")}},
                     {{"POSITION", b.AddFloats({0, 0, 0, 0, 0, 0, 0, 0, 0, -1, 0, 0}, "VEC3")}}};
  b.json()["meshes"][0]["weights"] = {0.5, 0};
  b.AddNode("posed_by_node", 0, {5, 0, 0});
  b.json()["nodes"][1]["weights"] = {1, 1};
  GltfAsset a = LoadGlb(b, dir);
  EXPECT_TRUE(a.warnings.empty()) << AllWarnings(a);
  ASSERT_EQ(a.meshes.size(), 2u);  // one per set of weights
  ASSERT_EQ(a.instances.size(), 2u);
  const Mesh& by_mesh = a.meshes[a.instances[0].mesh];
  const Mesh& by_node = a.meshes[a.instances[1].mesh];
  for (const auto& p : by_mesh.positions) EXPECT_FLOAT_EQ(p.z(), 0.5f);
  for (const auto& p : by_node.positions) EXPECT_FLOAT_EQ(p.z(), 1.0f);
  EXPECT_EQ(by_node.positions[3], Eigen::Vector3f(-1, 1, 1));  // (0, 1, 0) + (0, 0, 1) + (-1, 0, 0)

  // An animation (of the weights, here) is not played, with a warning.
  const int times = b.AddFloats({0, 1}, "SCALAR");
  const int values = b.AddFloats({0, 0, 1, 1}, "SCALAR");
  nlohmann::json animation;
  animation["samplers"] = nlohmann::json::array({{{"input", times}, {"output", values}}});
  animation["channels"] = nlohmann::json::array({{{"sampler", 0}, {"target", {{"node", 1}, {"path", "weights"}}}}});
  b.json()["animations"] = nlohmann::json::array({animation});
  GltfAsset animated = LoadGlb(b, dir);
  EXPECT_EQ(animated.meshes[animated.instances[1].mesh].positions, by_node.positions);
  EXPECT_EQ(AllWarnings(animated), "model.glb: 1 animation not played: the nodes' transforms and morph weights are "
                                   "used as written\n");

  b.json()["nodes"][1]["weights"] = {1};
  EXPECT_THAT(ErrorOf([&] { LoadGlb(b, dir); }),
              HasSubstr("model.glb: /nodes/1/weights: 1 weights for the 2 morph targets of /meshes/0/primitives/0"));
}

// Blender exports its camera and lamps with the meshes; they are not used (the
// scene file sets the sensor and the light) and one warning says so.
TEST(GltfExporters, CamerasAndLightsAreIgnoredWithOneWarning) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}}};
  b.json()["extensionsUsed"] = {"KHR_lights_punctual"};
  b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 100}},
                                                             {{"type", "directional"}}};
  b.AddNode("camera", -1);
  b.json()["nodes"][1]["camera"] = 0;
  b.AddNode("lamp", -1);
  b.json()["nodes"][2]["extensions"]["KHR_lights_punctual"] = {{"light", 1}};
  GltfAsset a = LoadGlb(b, dir);
  EXPECT_EQ(a.instances.size(), 1u);
  EXPECT_EQ(AllWarnings(a), "model.glb: 1 camera and 2 KHR_lights_punctual lights ignored (the scene file sets the "
                            "sensor and the lights)\n");
}

// ------------------------------------------------------------------ node hierarchy

TEST(GltfExporters, NodeWithSeveralParentsIsPlacedUnderEach) {
  TempDir dir;
  GltfBuilder b;
  const int mesh = b.AddTriangleMesh("square", test::SquarePositions(), test::SquareNormals(), {},
                                     test::SquareIndices());
  const int child = b.AddNode("child", mesh, {}, false);
  b.AddNode("left", -1, {0, 0, 0});
  b.AddNode("right", -1, {5, 0, 0});
  b.json()["nodes"][1]["children"] = {child};
  b.json()["nodes"][2]["children"] = {child};
  GltfAsset a = LoadGlb(b, dir);
  ASSERT_EQ(a.meshes.size(), 1u);
  ASSERT_EQ(a.instances.size(), 2u);
  EXPECT_DOUBLE_EQ(a.instances[0].file_from_mesh.translation().x(), 0.0);
  EXPECT_DOUBLE_EQ(a.instances[1].file_from_mesh.translation().x(), 5.0);
  EXPECT_THAT(AllWarnings(a), HasSubstr("model.glb: node \"child\" has 2 parents (glTF asks for a tree); it is "
                                        "placed under each"));

  // The same root listed twice is one placement, not two coincident copies.
  b.json()["scenes"][0]["nodes"].push_back(1);
  GltfAsset a2 = LoadGlb(b, dir);
  EXPECT_EQ(a2.instances.size(), 2u);
  EXPECT_THAT(AllWarnings(a2), HasSubstr("model.glb: /scenes/0/nodes/2: node 1 is listed twice; placed once"));

  // A cycle is still an error.
  b.json()["nodes"][0]["children"] = {1};
  EXPECT_THAT(ErrorOf([&] { LoadGlb(b, dir); }), HasSubstr("(the node hierarchy has a cycle)"));
}

// Several scenes and no "scene": scene 0 is loaded, and the warning says so.
TEST(GltfExporters, WithoutADefaultSceneTheFirstOfSeveralIsLoaded) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.AddNode("elsewhere", 0, {5, 0, 0}, false);
  b.json()["scenes"].push_back({{"nodes", {1}}});
  b.json().erase("scene");
  GltfAsset a = LoadGlb(b, dir);
  ASSERT_EQ(a.instances.size(), 1u);
  EXPECT_EQ(a.instances[0].node_name, "square_node");
  EXPECT_EQ(AllWarnings(a), "model.glb: no default scene (\"scene\"); scene 0 of 2 is loaded\n");
  b.json()["scene"] = 1;
  GltfAsset a1 = LoadGlb(b, dir);
  ASSERT_EQ(a1.instances.size(), 1u);
  EXPECT_EQ(a1.instances[0].node_name, "elsewhere");
  EXPECT_TRUE(a1.warnings.empty()) << AllWarnings(a1);
}

// ------------------------------------------------------------------ vertex buffers

// Multi-material meshes (three.js geometry groups, older Sketchfab exports) give
// every primitive the same POSITION / NORMAL accessors, each primitive indexing
// its part. Each primitive keeps only the vertices it uses, so the mesh holds each
// vertex once, not once per primitive.
TEST(GltfExporters, PrimitivesSharingAVertexBufferKeepOnlyTheirVertices) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  auto& prims = b.json()["meshes"][0]["primitives"];
  nlohmann::json second = prims[0];
  prims[0]["indices"] = b.AddIndices({0, 1, 2}, 5123);
  second["indices"] = b.AddIndices({0, 2, 3}, 5123);
  second["material"] = b.AddMaterial("other", {1, 0, 0, 1}, 0, 0.5);
  prims.push_back(second);
  GltfAsset a = LoadGlb(b, dir);
  ASSERT_EQ(a.meshes.size(), 1u);
  const Mesh& m = a.meshes[0];
  ASSERT_EQ(m.TriangleCount(), 2u);
  EXPECT_EQ(m.VertexCount(), 6u);  // 3 + 3 (8 before: all 4 per primitive)
  for (size_t t = 0; t < 2; ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t want = t == 0 ? std::vector<uint32_t>{0, 1, 2}[size_t(k)] : std::vector<uint32_t>{0, 2, 3}[size_t(k)];
      EXPECT_EQ(m.positions[m.indices[3 * t + size_t(k)]],
                Eigen::Vector3f(test::SquarePositions()[3 * want], test::SquarePositions()[3 * want + 1], 0));
    }
  }
}

// A vertex no triangle uses may hold anything (NaN here, as point-cloud meshing
// writes for invalid depth): it is dropped; a used NaN vertex is still an error.
TEST(GltfExporters, UnusedVerticesAreNotCheckedNorKept) {
  TempDir dir;
  GltfBuilder b;
  std::vector<float> p = test::SquarePositions(), n = test::SquareNormals();
  p.insert(p.end(), 3, std::nanf(""));
  n.insert(n.end(), {0, 0, 1});
  b.AddNode("part", b.AddTriangleMesh("part", p, n, {}, test::SquareIndices()));
  GltfAsset a = LoadGlb(b, dir);
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].VertexCount(), 4u);
  EXPECT_TRUE(a.meshes[0].Bounds().isApprox(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 0))));

  b.json()["meshes"][0]["primitives"][0]["indices"] = b.AddIndices({0, 1, 4});
  EXPECT_THAT(ErrorOf([&] { LoadGlb(b, dir); }), HasSubstr("model.glb: /accessors/0: position 4 is not finite (nan)"));
}

// ------------------------------------------------------------------ file names

// Exporters on Windows write backslashes in uris and names whose letter case
// differs from the files' (harmless on a case-insensitive file system): the files
// are found all the same. A file that does not exist in any of these forms is
// still an error naming the path looked for.
TEST(GltfExporters, UrisWithBackslashesOrAnotherLetterCaseFindTheirFiles) {
  TempDir dir;
  std::filesystem::create_directories(dir / "Textures");
  WriteImage(dir / "Textures" / "Wood.png", Image<uint8_t>(1, 1, 4, 255));
  GltfBuilder b = test::SquareBuilder(true, true);
  b.json()["textures"] = {{{"source", 0}}};
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("wood", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  for (const char* uri : {"Textures\\Wood.png", "textures/wood.PNG", "TEXTURES\\wood.png"}) {
    b.json()["images"] = {{{"uri", uri}}};
    b.WriteGltf(dir / "model.gltf", false);
    std::filesystem::rename(dir / "model.bin", dir / "Model.bin");  // the buffer's uri says model.bin
    GltfAsset a = LoadGltf(dir / "model.gltf");
    ASSERT_EQ(a.materials.size(), 1u) << uri;
    EXPECT_TRUE(a.materials[0].base_color_texture) << uri;
    EXPECT_EQ(a.meshes.at(0).TriangleCount(), 2u) << uri;
    std::filesystem::remove(dir / "Model.bin");
  }
  b.json()["images"] = {{{"uri", "Textures\\Oak.png"}}};
  b.WriteGltf(dir / "model.gltf", false);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "model.gltf", "model.gltf"); }),
              HasSubstr("model.gltf: /images/0/uri: texture image file not found (looked for "));
}

// A uri may be a file: URI naming an absolute path (converters write them), and a
// '+' in a relative uri is a plus (tinygltf alone reads it as a space, form
// encoding). Remote URIs, and file: URIs on another host, are refused by name.
TEST(GltfExporters, FileUrisAndPlusSignsNameTheirFiles) {
  TempDir dir;
  std::filesystem::create_directories(dir / "my parts");
  WriteImage(dir / "my parts" / "wood+oak.png", Image<uint8_t>(1, 1, 4, 255));
  GltfBuilder b = test::SquareBuilder(true, true);
  b.json()["textures"] = {{{"source", 0}}};
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("wood", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  const std::string abs = std::filesystem::absolute(dir.path()).lexically_normal().string();
  for (const std::string& uri : {std::string("my%20parts/wood+oak.png"), "file://" + abs + "/my%20parts/wood+oak.png",
                                 "file://localhost" + abs + "/my parts/wood%2Boak.png"}) {
    b.json()["images"] = {{{"uri", uri}}};
    b.WriteGltf(dir / "model.gltf", false);
    test::WriteText(dir / "model2.gltf", b.ToGltf("file://" + abs + "/model.bin"));
    for (const char* name : {"model.gltf", "model2.gltf"}) {
      GltfAsset a = LoadGltf(dir / name, name);
      ASSERT_EQ(a.materials.size(), 1u) << uri;
      EXPECT_TRUE(a.materials[0].base_color_texture) << name << " " << uri;
      EXPECT_EQ(a.meshes.at(0).TriangleCount(), 2u) << name << " " << uri;
    }
  }
  b.json()["images"] = {{{"uri", "https://example.com/wood.png"}}};
  b.WriteGltf(dir / "model.gltf", false);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "model.gltf", "model.gltf"); }),
              HasSubstr("model.gltf: /images/0/uri: \"https://example.com/wood.png\" is a https: URI; only local "
                        "files are read"));
  b.json()["images"] = {{{"uri", "file://server/share/wood.png"}}};
  b.WriteGltf(dir / "model.gltf", false);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "model.gltf", "model.gltf"); }),
              HasSubstr("model.gltf: /images/0/uri: \"file://server/share/wood.png\" names a file on host \"server\""));
}

// ------------------------------------------------------------------ units

TEST(GltfExporters, AnObjectTooLargeForTheScannerIsFlagged) {
  TempDir dir;
  GltfBuilder b;
  std::vector<float> p = test::SquarePositions();
  for (float& x : p) x *= 40;  // a 40 mm part written in millimetres: 40 m in glTF's metres
  b.AddNode("part", b.AddTriangleMesh("part", p, test::SquareNormals(), {}, test::SquareIndices()));
  b.WriteGlb(dir / "part.glb");
  const std::string scene = R"({"objects": [{"name": "part", "gltf": "part.glb"SCALE}],
    "sensor": {"camera": {"resolution": [8, 8], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}}})";
  auto load = [&](const std::string& scale) {
    std::string text = scene;
    text.replace(text.find("SCALE"), 5, scale);
    test::WriteText(dir / "scene.json", text);
    std::string all;
    for (const auto& w : LoadSceneGeometry(LoadSceneFile(dir / "scene.json")).warnings) all += w + "\n";
    return all;
  };
  EXPECT_THAT(load(""), HasSubstr("object \"part\" is 40 m across; glTF is in metres: if the file is in "
                                  "millimetres, give the object \"scale\": 0.001"));
  EXPECT_THAT(load(R"(, "scale": 0.001)"), Not(HasSubstr(" across")));
}

}  // namespace
}  // namespace lt

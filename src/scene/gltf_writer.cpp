#include "scene/gltf_writer.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace lt {

namespace {

int ComponentsOf(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT4") return 16;
  throw std::invalid_argument("GltfBuilder: unsupported accessor type " + type);
}

void WriteBytes(const std::filesystem::path& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

void AppendU32(std::vector<uint8_t>& v, uint32_t x) {
  uint8_t b[4];
  std::memcpy(b, &x, 4);
  v.insert(v.end(), b, b + 4);
}

}  // namespace

GltfBuilder::GltfBuilder() {
  doc_ = {{"asset", {{"version", "2.0"}, {"generator", "lasertwin"}}},
          {"scene", 0},
          {"scenes", nlohmann::json::array({{{"nodes", nlohmann::json::array()}}})}};
}

int GltfBuilder::AddBufferView(const void* data, size_t bytes, int byte_stride) {
  while (bin_.size() % 4 != 0) bin_.push_back(0);
  size_t offset = bin_.size();
  const auto* p = static_cast<const uint8_t*>(data);
  bin_.insert(bin_.end(), p, p + bytes);
  nlohmann::json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
  if (byte_stride > 0) view["byteStride"] = byte_stride;
  doc_["bufferViews"].push_back(view);
  return int(doc_["bufferViews"].size()) - 1;
}

int GltfBuilder::AddAccessor(int buffer_view, int component_type, size_t count, const std::string& type,
                             bool normalized, size_t byte_offset) {
  nlohmann::json a = {{"bufferView", buffer_view}, {"componentType", component_type}, {"count", count}, {"type", type}};
  if (byte_offset) a["byteOffset"] = byte_offset;
  if (normalized) a["normalized"] = true;
  doc_["accessors"].push_back(a);
  return int(doc_["accessors"].size()) - 1;
}

int GltfBuilder::AddFloats(const std::vector<float>& values, const std::string& type) {
  const int n = ComponentsOf(type);
  if (values.empty() || values.size() % size_t(n) != 0) throw std::invalid_argument("GltfBuilder: bad float count");
  int view = AddBufferView(values.data(), values.size() * sizeof(float));
  int acc = AddAccessor(view, 5126, values.size() / size_t(n), type);
  if (n == 3) {
    std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < values.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], double(values[i]));
      hi[i % 3] = std::max(hi[i % 3], double(values[i]));
    }
    doc_["accessors"][size_t(acc)]["min"] = lo;
    doc_["accessors"][size_t(acc)]["max"] = hi;
  }
  return acc;
}

int GltfBuilder::AddIndices(const std::vector<uint32_t>& indices, int component_type) {
  std::vector<uint8_t> bytes;
  for (uint32_t i : indices) {
    if (component_type == 5121) {
      bytes.push_back(uint8_t(i));
    } else if (component_type == 5123) {
      uint16_t v = uint16_t(i);
      bytes.insert(bytes.end(), reinterpret_cast<uint8_t*>(&v), reinterpret_cast<uint8_t*>(&v) + 2);
    } else {
      bytes.insert(bytes.end(), reinterpret_cast<uint8_t*>(&i), reinterpret_cast<uint8_t*>(&i) + 4);
    }
  }
  int view = AddBufferView(bytes.data(), bytes.size());
  return AddAccessor(view, component_type, indices.size(), "SCALAR");
}

int GltfBuilder::AddTriangleMesh(const std::string& name, const std::vector<float>& positions,
                                 const std::vector<float>& normals, const std::vector<float>& texcoords,
                                 const std::vector<uint32_t>& indices, int material, int mode) {
  nlohmann::json prim = {{"attributes", {{"POSITION", AddFloats(positions, "VEC3")}}}};
  if (!normals.empty()) prim["attributes"]["NORMAL"] = AddFloats(normals, "VEC3");
  if (!texcoords.empty()) prim["attributes"]["TEXCOORD_0"] = AddFloats(texcoords, "VEC2");
  if (!indices.empty()) prim["indices"] = AddIndices(indices);
  if (material >= 0) prim["material"] = material;
  if (mode != 4) prim["mode"] = mode;
  doc_["meshes"].push_back({{"name", name}, {"primitives", nlohmann::json::array({prim})}});
  return int(doc_["meshes"].size()) - 1;
}

int GltfBuilder::AddMaterial(const std::string& name, const std::vector<double>& base_color_rgba, double metallic,
                             double roughness, const std::vector<double>& emissive) {
  doc_["materials"].push_back({{"name", name},
                               {"pbrMetallicRoughness",
                                {{"baseColorFactor", base_color_rgba},
                                 {"metallicFactor", metallic},
                                 {"roughnessFactor", roughness}}},
                               {"emissiveFactor", emissive}});
  return int(doc_["materials"].size()) - 1;
}

int GltfBuilder::AddNode(const std::string& name, int mesh, const std::vector<double>& translation, bool root) {
  nlohmann::json node = {{"name", name}};
  if (mesh >= 0) node["mesh"] = mesh;
  if (!translation.empty()) node["translation"] = translation;
  doc_["nodes"].push_back(node);
  int index = int(doc_["nodes"].size()) - 1;
  if (root) doc_["scenes"][0]["nodes"].push_back(index);
  return index;
}

nlohmann::json GltfBuilder::Finalized(const std::string& bin_uri, bool with_buffer_uri) const {
  nlohmann::json doc = doc_;
  if (!bin_.empty() && !doc.contains("buffers")) {
    nlohmann::json buffer = {{"byteLength", bin_.size()}};
    if (with_buffer_uri) buffer["uri"] = bin_uri;
    doc["buffers"] = nlohmann::json::array({buffer});
  }
  return doc;
}

std::vector<uint8_t> GltfBuilder::ToGlb() const {
  std::string text = Finalized("", false).dump();
  while (text.size() % 4 != 0) text += ' ';
  std::vector<uint8_t> bin = bin_;
  while (bin.size() % 4 != 0) bin.push_back(0);
  std::vector<uint8_t> out;
  size_t total = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size());
  AppendU32(out, 0x46546C67);
  AppendU32(out, 2);
  AppendU32(out, uint32_t(total));
  AppendU32(out, uint32_t(text.size()));
  AppendU32(out, 0x4E4F534A);
  out.insert(out.end(), text.begin(), text.end());
  if (!bin.empty()) {
    AppendU32(out, uint32_t(bin.size()));
    AppendU32(out, 0x004E4942);
    out.insert(out.end(), bin.begin(), bin.end());
  }
  return out;
}

std::string GltfBuilder::ToGltf(const std::string& bin_uri) const {
  std::string uri = bin_uri.empty() ? "data:application/octet-stream;base64," + Base64Encode(bin_.data(), bin_.size())
                                    : bin_uri;
  return Finalized(uri, true).dump(1);
}

void GltfBuilder::WriteGlb(const std::filesystem::path& path) const {
  auto bytes = ToGlb();
  WriteBytes(path, bytes.data(), bytes.size());
}

void GltfBuilder::WriteGltf(const std::filesystem::path& path, bool embedded) const {
  std::string bin_name = path.stem().string() + ".bin";
  std::string text = ToGltf(embedded ? "" : bin_name);
  WriteBytes(path, text.data(), text.size());
  if (!embedded) WriteBytes(path.parent_path() / bin_name, bin_.data(), bin_.size());
}

}  // namespace lt

#include "scene/gltf_accessors.h"

#include <tiny_gltf.h>

#include <cstring>
#include <type_traits>
#include <limits>

#include "core/error.h"

namespace lt {

namespace {

constexpr size_t kMaxElementsWithoutView = size_t(1) << 28;

int ComponentSize(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;  // DOUBLE and INT are not glTF 2.0 accessor types
  }
}

int ComponentsOfType(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT4: return 16;  // no column padding at any component size (skins' inverse bind matrices)
    default: return 0;  // MAT2 and MAT3 (padded columns) are not read
  }
}

const char* TypeName(int components) {
  switch (components) {
    case 1: return "SCALAR";
    case 2: return "VEC2";
    case 3: return "VEC3";
    case 4: return "VEC4";
    case 16: return "MAT4";
    default: return "a matrix";
  }
}

// a + b <= limit without overflow.
bool FitsIn(uint64_t a, uint64_t b, uint64_t limit) { return a <= limit && b <= limit - a; }

// A checked window of bytes inside a buffer view.
struct ByteRange {
  const unsigned char* data = nullptr;
  uint64_t size = 0;
};

[[noreturn]] void Fail(const GltfSource& src, const std::string& array, int index, const std::string& m) {
  throw InputError(GltfWhere(src, array, index), m);
}

ByteRange BufferViewBytes(const GltfSource& src, int bv_index, const std::string& user) {
  const auto& m = src.model;
  if (bv_index < 0 || size_t(bv_index) >= m.bufferViews.size()) {
    throw InputError(user, "bufferView " + std::to_string(bv_index) + " does not exist (" +
                               std::to_string(m.bufferViews.size()) + " buffer views)");
  }
  const tinygltf::BufferView& bv = m.bufferViews[size_t(bv_index)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= m.buffers.size()) {
    Fail(src, "bufferViews", bv_index, "buffer " + std::to_string(bv.buffer) + " does not exist");
  }
  const tinygltf::Buffer& buf = m.buffers[size_t(bv.buffer)];
  if (!FitsIn(bv.byteOffset, bv.byteLength, buf.data.size())) {
    const bool overflow = bv.byteLength > UINT64_MAX - bv.byteOffset;
    const std::string end = overflow ? std::to_string(bv.byteOffset) + " + " + std::to_string(bv.byteLength)
                                     : std::to_string(uint64_t(bv.byteOffset) + bv.byteLength);
    Fail(src, "bufferViews", bv_index,
         "byte range [" + std::to_string(bv.byteOffset) + ", " + end + ") is outside buffer " +
             std::to_string(bv.buffer) + " (" + std::to_string(buf.data.size()) + " bytes)");
  }
  return {buf.data.data() + bv.byteOffset, bv.byteLength};
}

// Converts one component at p to float, glTF 2.0 normalisation rules.
template <typename T>
float ToFloat(const unsigned char* p, bool normalized) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::is_same_v<T, float>) {
    return v;
  } else {
    if (!normalized) return float(v);
    constexpr double kMax = double(std::numeric_limits<T>::max());
    double f = double(v) / kMax;
    return float(f < -1.0 ? -1.0 : f);
  }
}

float ComponentToFloat(int component_type, const unsigned char* p, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return ToFloat<int8_t>(p, normalized);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return ToFloat<uint8_t>(p, normalized);
    case TINYGLTF_COMPONENT_TYPE_SHORT: return ToFloat<int16_t>(p, normalized);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return ToFloat<uint16_t>(p, normalized);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return ToFloat<uint32_t>(p, normalized);
    default: return ToFloat<float>(p, false);
  }
}

uint32_t ComponentToIndex(int component_type, const unsigned char* p) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// The checked layout of an accessor: where element i starts.
struct Layout {
  ByteRange bytes;  // empty when the accessor has no bufferView (all zeros)
  uint64_t stride = 0;
  uint64_t offset = 0;
  size_t count = 0;
  int components = 0;
  int component_type = 0;
  bool normalized = false;
  const unsigned char* Element(size_t i) const { return bytes.data + offset + i * stride; }
};

Layout CheckAccessor(const GltfSource& src, int index) {
  const auto& m = src.model;
  if (index < 0 || size_t(index) >= m.accessors.size()) {
    throw InputError(src.file, "accessor " + std::to_string(index) + " does not exist (" +
                                   std::to_string(m.accessors.size()) + " accessors)");
  }
  const tinygltf::Accessor& a = m.accessors[size_t(index)];
  std::string where = GltfWhere(src, "accessors", index);
  Layout l;
  l.count = a.count;
  l.components = ComponentsOfType(a.type);
  l.component_type = a.componentType;
  l.normalized = a.normalized;
  int csize = ComponentSize(a.componentType);
  if (csize == 0) throw InputError(where, "unsupported componentType " + std::to_string(a.componentType));
  if (l.components == 0) throw InputError(where, "matrix accessors are not supported here");
  if (a.count == 0) throw InputError(where, "count must be >= 1");
  uint64_t elem = uint64_t(csize) * uint64_t(l.components);
  if (a.bufferView < 0) {
    // No bufferView: all zeros (glTF 2.0 3.6.2.1), then the sparse values if any.
    // Without a buffer view nothing in the file bounds the count: cap it.
    if (a.count > kMaxElementsWithoutView) {
      throw InputError(where, "count " + std::to_string(a.count) + " is implausibly large for an accessor without a bufferView (at most " +
                                  std::to_string(kMaxElementsWithoutView) + ")");
    }
    return l;
  }
  l.bytes = BufferViewBytes(src, a.bufferView, where);
  const tinygltf::BufferView& bv = m.bufferViews[size_t(a.bufferView)];
  l.stride = bv.byteStride != 0 ? bv.byteStride : elem;
  if (l.stride < elem) {
    Fail(src, "bufferViews", a.bufferView,
         "byteStride " + std::to_string(l.stride) + " is smaller than an element of accessor " +
             std::to_string(index) + " (" + std::to_string(elem) + " bytes)");
  }
  l.offset = a.byteOffset;
  // Last element must end inside the view: offset + stride * (count - 1) + elem <= size.
  uint64_t last = uint64_t(a.count - 1);
  bool fits = last <= (std::numeric_limits<uint64_t>::max() - elem) / l.stride &&
              FitsIn(l.offset, last * l.stride + elem, l.bytes.size);
  if (!fits) {
    throw InputError(where, std::to_string(a.count) + " elements of " + std::to_string(elem) +
                                " bytes (stride " + std::to_string(l.stride) + ") from byte " +
                                std::to_string(l.offset) + " do not fit in bufferView " +
                                std::to_string(a.bufferView) + " (" + std::to_string(l.bytes.size) +
                                " bytes)");
  }
  return l;
}

// Applies sparse substitution: calls set(element_index, pointer_to_value_bytes).
template <typename SetFn>
void ApplySparse(const GltfSource& src, int index, const Layout& l, SetFn set) {
  const tinygltf::Accessor& a = src.model.accessors[size_t(index)];
  if (!a.sparse.isSparse) return;
  std::string where = GltfWhere(src, "accessors", index) + "/sparse";
  const auto& sp = a.sparse;
  if (sp.count < 1 || size_t(sp.count) > a.count) {
    throw InputError(where, "count must be in [1, " + std::to_string(a.count) + "], got " +
                                std::to_string(sp.count));
  }
  int isize = ComponentSize(sp.indices.componentType);
  if (isize == 0 || sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
      sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
      sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
    throw InputError(where + "/indices", "componentType must be an unsigned byte, short or int, got " +
                                             std::to_string(sp.indices.componentType));
  }
  uint64_t elem = uint64_t(ComponentSize(l.component_type)) * uint64_t(l.components);
  ByteRange ib = BufferViewBytes(src, sp.indices.bufferView, where + "/indices");
  ByteRange vb = BufferViewBytes(src, sp.values.bufferView, where + "/values");
  if (sp.indices.byteOffset < 0 || !FitsIn(uint64_t(sp.indices.byteOffset), uint64_t(sp.count) * isize, ib.size)) {
    throw InputError(where + "/indices", std::to_string(sp.count) + " indices do not fit in bufferView " +
                                             std::to_string(sp.indices.bufferView));
  }
  if (sp.values.byteOffset < 0 || !FitsIn(uint64_t(sp.values.byteOffset), uint64_t(sp.count) * elem, vb.size)) {
    throw InputError(where + "/values", std::to_string(sp.count) + " values do not fit in bufferView " +
                                            std::to_string(sp.values.bufferView));
  }
  int64_t previous = -1;
  for (int k = 0; k < sp.count; ++k) {
    uint32_t target = ComponentToIndex(sp.indices.componentType, ib.data + sp.indices.byteOffset + uint64_t(k) * isize);
    if (target >= a.count) {
      throw InputError(where + "/indices", "index " + std::to_string(target) + " is past the accessor's " +
                                               std::to_string(a.count) + " elements");
    }
    if (int64_t(target) <= previous) {
      throw InputError(where + "/indices", "indices must increase strictly (got " + std::to_string(target) +
                                               " after " + std::to_string(previous) + ")");
    }
    previous = target;
    set(size_t(target), vb.data + sp.values.byteOffset + uint64_t(k) * elem);
  }
}

}  // namespace

std::string GltfWhere(const GltfSource& src, const std::string& array, int index) {
  return src.file + ": /" + array + "/" + std::to_string(index);
}

size_t AccessorCount(const GltfSource& src, int index) { return CheckAccessor(src, index).count; }

std::vector<float> ReadFloatAccessor(const GltfSource& src, int index, int components) {
  Layout l = CheckAccessor(src, index);
  if (l.components != components) {
    throw InputError(GltfWhere(src, "accessors", index),
                     std::string("type must be ") + TypeName(components) + ", got " + TypeName(l.components));
  }
  const int csize = ComponentSize(l.component_type);
  std::vector<float> out(l.count * size_t(components), 0.0f);
  if (l.bytes.data != nullptr) {
    if (l.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT && l.stride == uint64_t(4 * components)) {
      std::memcpy(out.data(), l.Element(0), out.size() * sizeof(float));
    } else {
      for (size_t i = 0; i < l.count; ++i) {
        const unsigned char* e = l.Element(i);
        for (int c = 0; c < components; ++c) {
          out[i * components + c] = ComponentToFloat(l.component_type, e + c * csize, l.normalized);
        }
      }
    }
  }
  ApplySparse(src, index, l, [&](size_t i, const unsigned char* e) {
    for (int c = 0; c < components; ++c) {
      out[i * components + c] = ComponentToFloat(l.component_type, e + c * csize, l.normalized);
    }
  });
  return out;
}

std::vector<uint32_t> ReadIndexAccessor(const GltfSource& src, int index) {
  Layout l = CheckAccessor(src, index);
  std::string where = GltfWhere(src, "accessors", index);
  if (l.components != 1) throw InputError(where, std::string("indices must be SCALAR, got ") + TypeName(l.components));
  if (l.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      l.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      l.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    throw InputError(where, "indices must be unsigned bytes, shorts or ints, got componentType " +
                                std::to_string(l.component_type));
  }
  std::vector<uint32_t> out(l.count, 0);
  if (l.bytes.data != nullptr) {
    for (size_t i = 0; i < l.count; ++i) out[i] = ComponentToIndex(l.component_type, l.Element(i));
  }
  ApplySparse(src, index, l, [&](size_t i, const unsigned char* e) { out[i] = ComponentToIndex(l.component_type, e); });
  return out;
}

}  // namespace lt

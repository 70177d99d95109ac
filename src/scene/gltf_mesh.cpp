// ConvertGltfMesh (gltf_mesh.h) and the accessor checks it shares with the skinning and
// morph targets of a primitive, which are in gltf_skin_morph.cpp.
#include "scene/gltf_mesh.h"

#include <algorithm>

#include <tiny_gltf.h>

#include <cmath>
#include <utility>

#include "core/error.h"
#include "scene/gltf_skin_morph.h"

namespace lt {

namespace gltf_mesh_detail {

// Fails when accessor `index`, referenced at `where`, does not exist.
void CheckAccessorRef(const GltfSource& src, int index, const std::string& where) {
  if (index < 0 || size_t(index) >= src.model.accessors.size()) {
    throw InputError(where, "accessor " + std::to_string(index) + " does not exist (" +
                                std::to_string(src.model.accessors.size()) + " accessors)");
  }
}

// The accessor of an attribute, or -1 when the primitive has none.
int FindAttribute(const GltfSource& src, const tinygltf::Primitive& p, const char* name, const std::string& where) {
  auto it = p.attributes.find(name);
  if (it == p.attributes.end()) return -1;
  CheckAccessorRef(src, it->second, where + "/attributes/" + name);
  return it->second;
}

// Fails when any value is not finite; with `used`, only the values of the used
// elements are checked (a vertex no triangle uses cannot reach the render).
void CheckFinite(const GltfSource& src, int accessor, const std::vector<float>& v, int components,
                 const char* what, const std::vector<char>* used) {
  for (size_t i = 0; i < v.size(); ++i) {
    if (used != nullptr && !(*used)[i / size_t(components)]) continue;
    if (!std::isfinite(v[i])) {
      throw InputError(GltfWhere(src, "accessors", accessor),
                       std::string(what) + " " + std::to_string(i / components) + " is not finite (" +
                           FormatNumber(v[i]) + ")");
    }
  }
}

Eigen::Vector3f Vec3At(const std::vector<float>& v, size_t i) { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }

}  // namespace gltf_mesh_detail

using namespace gltf_mesh_detail;

namespace {

const char* ModeName(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS: return "points";
    case TINYGLTF_MODE_LINE: return "lines";
    case TINYGLTF_MODE_LINE_LOOP: return "line loop";
    case TINYGLTF_MODE_LINE_STRIP: return "line strip";
    case TINYGLTF_MODE_TRIANGLES: return "triangles";
    case TINYGLTF_MODE_TRIANGLE_STRIP: return "triangle strip";
    case TINYGLTF_MODE_TRIANGLE_FAN: return "triangle fan";
    default: return "unknown";
  }
}

// Corner list (3 per triangle) of a primitive, from its indices or implicit 0..n-1.
std::vector<uint32_t> Triangulate(const std::vector<uint32_t>& corners_in, int mode, const std::string& where) {
  const size_t n = corners_in.size();
  std::vector<uint32_t> tri;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (n % 3 != 0) {
      throw InputError(where, "a triangle list needs a multiple of 3 vertices, got " + std::to_string(n));
    }
    return corners_in;
  }
  if (n < 3) return tri;
  tri.reserve((n - 2) * 3);
  for (size_t i = 0; i + 2 < n; ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      // glTF 2.0 3.7.2.1: triangle i is {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}}.
      tri.insert(tri.end(), {corners_in[i], corners_in[i + 1 + i % 2], corners_in[i + 2 - i % 2]});
    } else {  // fan: {v_{i+1}, v_{i+2}, v_0}
      tri.insert(tri.end(), {corners_in[i + 1], corners_in[i + 2], corners_in[0]});
    }
  }
  return tri;
}

}  // namespace

Mesh ConvertGltfMesh(const GltfSource& src, int index, const std::vector<Material>& materials,
                     uint32_t default_material, GltfMeshStats* stats, std::vector<std::string>* warnings,
                     const GltfSkinPose* skin, const GltfMorphWeights* morph) {
  const tinygltf::Mesh& gm = src.model.meshes[size_t(index)];
  const std::string mesh_where = GltfWhere(src, "meshes", index);
  Mesh mesh;
  mesh.name = gm.name.empty() ? "mesh " + std::to_string(index) : gm.name;

  // The texture coordinates of each primitive: the set its material's base-colour
  // texture reads, else TEXCOORD_0 (-1: the primitive has neither).
  std::vector<int> uv_accessor(gm.primitives.size(), -1);
  std::vector<std::string> uv_name(gm.primitives.size(), "TEXCOORD_0");
  bool any_texcoords = false, any_colors = false, any_alphas = false;
  for (size_t pi = 0; pi < gm.primitives.size(); ++pi) {
    const tinygltf::Primitive& prim = gm.primitives[pi];
    const std::string where = mesh_where + "/primitives/" + std::to_string(pi);
    const bool own_material = prim.material >= 0 && size_t(prim.material) < materials.size();
    const int set = own_material ? materials[size_t(prim.material)].base_color_texcoord : 0;
    const std::string set_name = "TEXCOORD_" + std::to_string(set);
    uv_accessor[pi] = FindAttribute(src, prim, set_name.c_str(), where);
    if (uv_accessor[pi] >= 0) uv_name[pi] = set_name;
    stats->texcoords_not_set_0 |= uv_accessor[pi] >= 0 && set != 0;
    if (uv_accessor[pi] < 0 && set != 0) {
      uv_accessor[pi] = FindAttribute(src, prim, "TEXCOORD_0", where);
      warnings->push_back(src.file + ": mesh \"" + mesh.name + "\" primitive " + std::to_string(pi) +
                          ": material \"" + materials[size_t(prim.material)].name + "\" reads " + set_name +
                          ", which the primitive does not have; TEXCOORD_0 is used" +
                          (uv_accessor[pi] < 0 ? " (it has none either: all coordinates 0)" : ""));
    }
    any_texcoords |= uv_accessor[pi] >= 0;
    any_colors |= prim.attributes.count("COLOR_0") != 0;
    if (auto c = prim.attributes.find("COLOR_0"); c != prim.attributes.end() && c->second >= 0 &&
                                                  size_t(c->second) < src.model.accessors.size()) {
      any_alphas |= src.model.accessors[size_t(c->second)].type == TINYGLTF_TYPE_VEC4;
    }
  }

  for (size_t pi = 0; pi < gm.primitives.size(); ++pi) {
    const tinygltf::Primitive& prim = gm.primitives[pi];
    const std::string where = mesh_where + "/primitives/" + std::to_string(pi);
    if (prim.mode == TINYGLTF_MODE_POINTS || prim.mode == TINYGLTF_MODE_LINE ||
        prim.mode == TINYGLTF_MODE_LINE_LOOP || prim.mode == TINYGLTF_MODE_LINE_STRIP) {
      stats->skipped_primitives.emplace_back(ModeName(prim.mode), pi);
      continue;
    }
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      throw InputError(where + "/mode", "unknown primitive mode " + std::to_string(prim.mode));
    }
    uint32_t material = default_material;
    if (prim.material >= 0) {
      if (size_t(prim.material) >= src.model.materials.size()) {
        throw InputError(where + "/material", "material " + std::to_string(prim.material) + " does not exist (" +
                                                  std::to_string(src.model.materials.size()) + " materials)");
      }
      material = uint32_t(prim.material);
    } else if (prim.material < -1) {
      throw InputError(where + "/material", "must be >= 0, got " + std::to_string(prim.material));
    } else {
      stats->uses_default_material = true;
    }

    const int pos_acc = FindAttribute(src, prim, "POSITION", where);
    if (pos_acc < 0) throw InputError(where + "/attributes", "missing required attribute POSITION");
    std::vector<float> pos = ReadFloatAccessor(src, pos_acc, 3);
    const size_t nverts = pos.size() / 3;
    if (nverts > size_t(UINT32_MAX)) throw InputError(where, "too many vertices");

    std::vector<uint32_t> corners;
    if (prim.indices >= 0) {
      CheckAccessorRef(src, prim.indices, where + "/indices");
      corners = ReadIndexAccessor(src, prim.indices);
      // The largest value of the index type restarts a strip or fan in OpenGL ES 3
      // and WebGL 2; glTF forbids it in indices (3.7.2.1), so it is refused, named.
      const int index_type = src.model.accessors[size_t(prim.indices)].componentType;
      const uint32_t restart = index_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 0xffu
                               : index_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 0xffffu
                                                                                      : 0xffffffffu;
      for (size_t i = 0; i < corners.size(); ++i) {
        if (corners[i] >= nverts) {
          throw InputError(GltfWhere(src, "accessors", prim.indices),
                           "index " + std::to_string(corners[i]) + " (element " + std::to_string(i) +
                               ") is past the vertex count " + std::to_string(nverts) +
                               (corners[i] == restart ? std::string(" (the primitive-restart value, which glTF does "
                                                                    "not allow in indices: write each strip or fan "
                                                                    "as its own primitive, or as triangles)")
                                                      : std::string()));
        }
      }
    } else {
      corners.resize(nverts);
      for (size_t i = 0; i < nverts; ++i) corners[i] = uint32_t(i);
    }
    std::vector<uint32_t> tri = Triangulate(corners, prim.mode, where);
    corners = {};
    // The vertices the triangles use: only they are checked and kept (several
    // primitives may share one large POSITION accessor, each using a part of it).
    std::vector<char> used(nverts, 0);
    for (uint32_t i : tri) used[i] = 1;
    CheckFinite(src, pos_acc, pos, 3, "position", &used);

    std::vector<float> nrm;
    if (int acc = FindAttribute(src, prim, "NORMAL", where); acc >= 0) {
      nrm = ReadFloatAccessor(src, acc, 3);
      if (nrm.size() != pos.size()) {
        throw InputError(GltfWhere(src, "accessors", acc), "NORMAL has " + std::to_string(nrm.size() / 3) +
                                                               " elements, POSITION " + std::to_string(nverts));
      }
      CheckFinite(src, acc, nrm, 3, "normal", &used);
    }
    std::vector<float> uv;
    if (int acc = uv_accessor[pi]; acc >= 0) {
      uv = ReadFloatAccessor(src, acc, 2);
      if (uv.size() / 2 != nverts) {
        throw InputError(GltfWhere(src, "accessors", acc), uv_name[pi] + " has " + std::to_string(uv.size() / 2) +
                                                               " elements, POSITION " + std::to_string(nverts));
      }
      CheckFinite(src, acc, uv, 2, "texture coordinate", &used);
    }

    // COLOR_0 (RGB or RGBA, linear; glTF 3.7.2.1): multiplies the base
    // colour (and its alpha the material's, read by MASK and BLEND materials);
    // a primitive without it in a mesh with it gets opaque white.
    std::vector<float> rgb, alpha;
    if (int acc = FindAttribute(src, prim, "COLOR_0", where); acc >= 0) {
      const tinygltf::Accessor& ca = src.model.accessors[size_t(acc)];
      // glTF 3.7.2.1: floats, or unsigned bytes / shorts that are normalized. Other
      // integers read as their raw values were clamped to white (a colour of
      // 0..255 bytes without "normalized": true, as some exporters write them).
      if (ca.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT &&
          !(ca.normalized && (ca.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                              ca.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))) {
        throw InputError(GltfWhere(src, "accessors", acc),
                         "COLOR_0 must be floats or normalized unsigned bytes or shorts (glTF 3.7.2.1), got "
                         "componentType " + std::to_string(ca.componentType) +
                             (ca.normalized ? "" : " without \"normalized\": true"));
      }
      if (ca.type != TINYGLTF_TYPE_VEC3 && ca.type != TINYGLTF_TYPE_VEC4) {
        throw InputError(GltfWhere(src, "accessors", acc),
                         std::string("COLOR_0 must be VEC3 or VEC4 (glTF 3.7.2.1), got ") +
                             (ca.type == TINYGLTF_TYPE_SCALAR ? "SCALAR" : ca.type == TINYGLTF_TYPE_VEC2 ? "VEC2" : "a matrix"));
      }
      const int components = ca.type == TINYGLTF_TYPE_VEC4 ? 4 : 3;
      const std::vector<float> c = ReadFloatAccessor(src, acc, components);
      if (c.size() / size_t(components) != nverts) {
        throw InputError(GltfWhere(src, "accessors", acc), "COLOR_0 has " + std::to_string(c.size() / size_t(components)) +
                                                               " elements, POSITION " + std::to_string(nverts));
      }
      CheckFinite(src, acc, c, components, "vertex colour", &used);
      rgb.resize(3 * nverts);
      for (size_t v = 0; v < nverts; ++v)
        for (int k = 0; k < 3; ++k) rgb[3 * v + size_t(k)] = std::clamp(c[size_t(components) * v + size_t(k)], 0.0f, 1.0f);
      if (components == 4) {
        alpha.resize(nverts);
        for (size_t v = 0; v < nverts; ++v) alpha[v] = std::clamp(c[4 * v + 3], 0.0f, 1.0f);
      }
    }
    auto color_of = [&](size_t v) { return rgb.empty() ? Eigen::Vector3f::Ones().eval() : Vec3At(rgb, v); };
    auto alpha_of = [&](size_t v) { return alpha.empty() ? 1.0f : alpha[v]; };

    ApplyMorphTargets(src, prim, where, morph, &pos, &nrm);
    if (morph != nullptr && !prim.targets.empty()) CheckFinite(src, pos_acc, pos, 3, "morphed position", &used);

    std::vector<char> mirrored;  // by vertex, when skinned
    if (skin != nullptr) {
      ApplySkin(src, prim, where, *skin, &pos, &nrm, &mirrored);
      CheckFinite(src, pos_acc, pos, 3, "skinned position", &used);
    }

    // Keep the non-degenerate triangles.
    size_t kept = 0;
    for (size_t t = 0; t < tri.size() / 3; ++t) {
      uint32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
      // A triangle the skin mirrors is turned round, so that its winding and
      // normals agree again (glTF: a negative determinant reverses the winding).
      if (!mirrored.empty() && mirrored[a] + mirrored[b] + mirrored[c] >= 2) std::swap(b, c);
      const Eigen::Vector3f pa = Vec3At(pos, a), pb = Vec3At(pos, b), pc = Vec3At(pos, c);
      if (a == b || b == c || a == c || IsDegenerateTriangle(pa, pb, pc)) {
        // A strip joins its runs by triangles with a repeated corner (index or
        // position): they are how strips are written, not a defect to report.
        const bool join = prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP &&
                          (a == b || b == c || a == c || pa == pb || pb == pc || pa == pc);
        if (!join) ++stats->degenerate_triangles;
        continue;
      }
      tri[3 * kept] = a;
      tri[3 * kept + 1] = b;
      tri[3 * kept + 2] = c;
      ++kept;
    }
    tri.resize(3 * kept);

    const size_t base = mesh.positions.size();
    if (!nrm.empty()) {
      // Shared vertices with the file's normals: the vertices the kept triangles
      // use, in their order in the file. Zero-length normals are replaced by the
      // area-weighted normal of the triangles around the vertex.
      std::vector<uint32_t> remap(nverts, UINT32_MAX);
      for (uint32_t i : tri) remap[i] = 0;
      size_t kept_vertices = 0;
      for (size_t v = 0; v < nverts; ++v) {
        if (remap[v] == 0) remap[v] = uint32_t(kept_vertices++);
      }
      if (base + kept_vertices > size_t(UINT32_MAX)) throw InputError(mesh_where, "too many vertices");
      mesh.positions.reserve(base + kept_vertices);
      mesh.normals.reserve(base + kept_vertices);
      if (any_texcoords) mesh.texcoords.reserve(base + kept_vertices);
      if (any_colors) mesh.colors.reserve(base + kept_vertices);
      if (any_alphas) mesh.alphas.reserve(base + kept_vertices);
      std::vector<uint32_t> zero;  // new indices
      for (size_t v = 0; v < nverts; ++v) {
        if (remap[v] == UINT32_MAX) continue;
        mesh.positions.push_back(Vec3At(pos, v));
        Eigen::Vector3f n = Vec3At(nrm, v);
        float len = n.norm();
        if (!(len > 1e-12f)) zero.push_back(remap[v]);
        mesh.normals.push_back(len > 1e-12f ? Eigen::Vector3f(n / len) : Eigen::Vector3f::Zero());
        if (any_texcoords) {
          mesh.texcoords.push_back(uv.empty() ? Eigen::Vector2f::Zero() : Eigen::Vector2f(uv[2 * v], uv[2 * v + 1]));
        }
        if (any_colors) mesh.colors.push_back(color_of(v));
        if (any_alphas) mesh.alphas.push_back(alpha_of(v));
      }
      for (uint32_t& i : tri) i = remap[i];
      if (!zero.empty()) {
        // Accumulate face normals only into the vertices whose normal was zero.
        std::vector<Eigen::Vector3d> acc(zero.size(), Eigen::Vector3d::Zero());
        std::vector<int64_t> slot(kept_vertices, -1);
        for (size_t k = 0; k < zero.size(); ++k) slot[zero[k]] = int64_t(k);
        const Eigen::Vector3f* p = mesh.positions.data() + base;
        for (size_t t = 0; t < tri.size() / 3; ++t) {
          Eigen::Vector3d fn = FaceNormal(p[tri[3 * t]], p[tri[3 * t + 1]], p[tri[3 * t + 2]]);
          for (int k = 0; k < 3; ++k) {
            if (slot[tri[3 * t + k]] >= 0) acc[size_t(slot[tri[3 * t + k]])] += fn;
          }
        }
        for (size_t k = 0; k < zero.size(); ++k) {
          mesh.normals[base + zero[k]] =
              acc[k].norm() > 0 ? Eigen::Vector3f(acc[k].normalized().cast<float>()) : Eigen::Vector3f::UnitZ();
        }
        warnings->push_back(src.file + ": mesh \"" + mesh.name + "\" primitive " + std::to_string(pi) + ": " +
                            std::to_string(zero.size()) + " zero-length normals replaced by face normals");
      }
      mesh.indices.reserve(mesh.indices.size() + tri.size());
      for (uint32_t i : tri) mesh.indices.push_back(uint32_t(base + i));
    } else {
      // No normals: glTF asks for flat shading, so every triangle gets its own
      // three vertices carrying the face normal.
      if (base + tri.size() > size_t(UINT32_MAX)) throw InputError(mesh_where, "too many vertices");
      mesh.positions.reserve(base + tri.size());
      mesh.normals.reserve(base + tri.size());
      if (any_texcoords) mesh.texcoords.reserve(base + tri.size());
      if (any_colors) mesh.colors.reserve(base + tri.size());
      if (any_alphas) mesh.alphas.reserve(base + tri.size());
      mesh.indices.reserve(mesh.indices.size() + tri.size());
      for (size_t t = 0; t < tri.size() / 3; ++t) {
        Eigen::Vector3f p[3] = {Vec3At(pos, tri[3 * t]), Vec3At(pos, tri[3 * t + 1]), Vec3At(pos, tri[3 * t + 2])};
        Eigen::Vector3f fn = FaceNormal(p[0], p[1], p[2]).normalized().cast<float>();
        for (int k = 0; k < 3; ++k) {
          mesh.indices.push_back(uint32_t(mesh.positions.size()));
          mesh.positions.push_back(p[k]);
          mesh.normals.push_back(fn);
          const uint32_t v = tri[3 * t + k];
          if (any_texcoords) {
            mesh.texcoords.push_back(uv.empty() ? Eigen::Vector2f::Zero() : Eigen::Vector2f(uv[2 * v], uv[2 * v + 1]));
          }
          if (any_colors) mesh.colors.push_back(color_of(v));
          if (any_alphas) mesh.alphas.push_back(alpha_of(v));
        }
      }
    }
    mesh.triangle_material.insert(mesh.triangle_material.end(), tri.size() / 3, material);
  }
  return mesh;
}

}  // namespace lt

// Surface materials: glTF 2.0 metallic-roughness (base colour, optional base-colour
// texture, metallic, roughness, emission) plus an optional subsurface term that
// blurs light inside translucent plastic (3D-printed PLA, ABS, ...).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>

#include "core/image.h"

namespace lt {

// glTF sampler wrap modes.
enum class WrapMode { kRepeat, kClampToEdge, kMirroredRepeat };

// A colour texture: 8-bit RGBA pixels as stored in the file (sRGB-encoded colour,
// linear alpha). Lookups decode sRGB to linear before filtering.
struct Texture {
  std::string name;  // file path or glTF image name, for messages
  Image<uint8_t> image;  // 4 channels
  WrapMode wrap_s = WrapMode::kRepeat;
  WrapMode wrap_t = WrapMode::kRepeat;

  // Bilinearly filtered linear RGBA at glTF texture coordinate uv (u right,
  // v down, (0,0) is the top-left corner of the top-left texel, (1,1) the
  // bottom-right corner of the bottom-right one), with the wrap modes applied.
  Eigen::Vector4f Sample(const Eigen::Vector2f& uv) const;
  // One texel, decoded to linear (x, y wrapped by the wrap modes).
  Eigen::Vector4f Texel(int x, int y) const;
};

// An affine map of texture coordinates (KHR_texture_transform): uv' = linear * uv + offset.
struct UvTransform {
  Eigen::Matrix2f linear = Eigen::Matrix2f::Identity();
  Eigen::Vector2f offset = Eigen::Vector2f::Zero();

  // KHR_texture_transform's T * R * S: scale, then rotate by `rotation` radians
  // counter-clockwise in UV space (u right, v down: u' = u cos + v sin,
  // v' = v cos - u sin), then offset.
  static UvTransform FromOffsetRotationScale(const Eigen::Vector2d& offset, double rotation,
                                             const Eigen::Vector2d& scale);
  Eigen::Vector2f Apply(const Eigen::Vector2f& uv) const { return linear * uv + offset; }
};

// sRGB transfer function, encoded 8-bit value -> linear [0, 1] (IEC 61966-2-1).
float SrgbToLinear(uint8_t v);

// Subsurface scattering parameters of a translucent material.
struct Subsurface {
  Eigen::Vector3d mean_free_path_m = Eigen::Vector3d::Zero();  // per RGB channel, > 0
  double mean_free_path_laser_m = 0;  // at the laser's wavelength, > 0
};

// glTF alphaMode: how the base colour's alpha (factor x texture alpha x COLOR_0
// alpha) covers the surface. kOpaque ignores it; kMask makes the surface a hole
// where alpha < alpha_cutoff; kBlend reads alpha as coverage: a ray meets the
// surface with probability alpha (docs/scene-format.md). EmbreeScene applies it,
// so every ray (camera, shadow, laser, ground truth) sees the same surface.
enum class AlphaMode { kOpaque, kMask, kBlend };

struct Material {
  std::string name;
  Eigen::Vector3f base_color = Eigen::Vector3f::Ones();  // linear, [0, 1]
  std::shared_ptr<const Texture> base_color_texture;     // multiplies base_color; may be null
  int base_color_texcoord = 0;                           // TEXCOORD_n the glTF texture reads (the mesh's
                                                         // texcoords hold that set for its primitives)
  UvTransform base_color_uv_transform;                   // applied to uv before the texture lookup
  float metallic = 0;                                    // [0, 1]
  float roughness = 1;                                   // [0, 1], perceptual (alpha = roughness^2)
  Eigen::Vector3f emissive = Eigen::Vector3f::Zero();    // radiance, W/(m^2 sr), >= 0
  bool double_sided = false;
  std::optional<Subsurface> subsurface;
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha = 1;                                       // baseColorFactor[3], [0, 1]
  float alpha_cutoff = 0.5f;                             // kMask: alpha below it is a hole, >= 0

  // Linear base colour at a texture coordinate (texture, read at
  // base_color_uv_transform(uv), times factor).
  Eigen::Vector3f BaseColorAt(const Eigen::Vector2f& uv) const;
  // The base colour's alpha at a texture coordinate (alpha times the texture's
  // alpha, bilinear as BaseColorAt), before the vertex colour's alpha.
  float AlphaAt(const Eigen::Vector2f& uv) const;
  // The smallest alpha AlphaAt can return (alpha times the texture's smallest
  // texel alpha). Reads every texel: call it once per material, not per ray.
  float MinAlpha() const;
  // Throws std::invalid_argument when a value is out of range or not finite.
  void Check() const;
};

// The material of a glTF primitive that names none: the glTF 2.0 default material
// (every property at its default: base colour white, metallic 1, roughness 1,
// no emission), named "default".
Material DefaultMaterial();

}  // namespace lt

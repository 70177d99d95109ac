#include "scene/material.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace lt {

namespace {

std::array<float, 256> MakeSrgbTable() {
  std::array<float, 256> t{};
  for (int i = 0; i < 256; ++i) {
    double c = i / 255.0;
    t[i] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
  }
  return t;
}

const std::array<float, 256>& SrgbTable() {
  static const std::array<float, 256> table = MakeSrgbTable();
  return table;
}

// Maps an integer texel coordinate into [0, n) by the wrap mode.
int Wrap(int i, int n, WrapMode mode) {
  switch (mode) {
    case WrapMode::kClampToEdge:
      return i < 0 ? 0 : (i >= n ? n - 1 : i);
    case WrapMode::kMirroredRepeat: {
      int period = 2 * n;
      int m = i % period;
      if (m < 0) m += period;
      return m < n ? m : period - 1 - m;
    }
    case WrapMode::kRepeat:
    default: {
      int m = i % n;
      return m < 0 ? m + n : m;
    }
  }
}

bool InUnit(float v) { return std::isfinite(v) && v >= 0.0f && v <= 1.0f; }

}  // namespace

float SrgbToLinear(uint8_t v) { return SrgbTable()[v]; }

Eigen::Vector4f Texture::Texel(int x, int y) const {
  int xi = Wrap(x, image.width, wrap_s);
  int yi = Wrap(y, image.height, wrap_t);
  const uint8_t* p = &image.At(xi, yi, 0);
  const auto& t = SrgbTable();
  return {t[p[0]], t[p[1]], t[p[2]], p[3] / 255.0f};
}

Eigen::Vector4f Texture::Sample(const Eigen::Vector2f& uv) const {
  if (image.empty() || image.channels != 4) return Eigen::Vector4f::Ones();
  // Texel centres sit at (i + 0.5) / width. Coordinates far outside [0, 1] are
  // reduced first (by whole periods, so repeat and mirrored repeat stay exact)
  // so the float-to-int conversion cannot overflow.
  auto reduce = [](float v, WrapMode mode) {
    if (!std::isfinite(v)) return 0.0f;
    if (mode == WrapMode::kClampToEdge) return std::clamp(v, -1.0f, 2.0f);
    return std::fabs(v) > 1e6f ? std::fmod(v, 2.0f) : v;
  };
  float x = reduce(uv.x(), wrap_s) * image.width - 0.5f;
  float y = reduce(uv.y(), wrap_t) * image.height - 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  int x0 = int(fx), y0 = int(fy);
  float ax = x - fx, ay = y - fy;
  Eigen::Vector4f top = (1 - ax) * Texel(x0, y0) + ax * Texel(x0 + 1, y0);
  Eigen::Vector4f bottom = (1 - ax) * Texel(x0, y0 + 1) + ax * Texel(x0 + 1, y0 + 1);
  return (1 - ay) * top + ay * bottom;
}

UvTransform UvTransform::FromOffsetRotationScale(const Eigen::Vector2d& offset, double rotation,
                                                 const Eigen::Vector2d& scale) {
  // The matrix of KHR_texture_transform's implementations and sample model
  // (three.js, Babylon.js, Blender, CesiumJS); the GLSL listing in the extension's
  // README is its transpose, a known erratum (KhronosGroup/glTF#1563).
  const double c = std::cos(rotation), s = std::sin(rotation);
  Eigen::Matrix2d r;
  r << c, s, -s, c;
  UvTransform t;
  t.linear = (r * scale.asDiagonal()).cast<float>();
  t.offset = offset.cast<float>();
  return t;
}

Eigen::Vector3f Material::BaseColorAt(const Eigen::Vector2f& uv) const {
  if (!base_color_texture) return base_color;
  return base_color.cwiseProduct(base_color_texture->Sample(base_color_uv_transform.Apply(uv)).head<3>());
}

float Material::AlphaAt(const Eigen::Vector2f& uv) const {
  if (!base_color_texture) return alpha;
  return alpha * base_color_texture->Sample(base_color_uv_transform.Apply(uv)).w();
}

float Material::MinAlpha() const {
  const Image<uint8_t>* image = base_color_texture ? &base_color_texture->image : nullptr;
  if (image == nullptr || image->empty() || image->channels != 4) return alpha;
  uint8_t lowest = 255;
  for (int y = 0; y < image->height && lowest > 0; ++y) {
    for (int x = 0; x < image->width; ++x) lowest = std::min(lowest, image->At(x, y, 3));
  }
  return alpha * (lowest / 255.0f);
}

void Material::Check() const {
  auto fail = [&](const std::string& m) { throw std::invalid_argument("material \"" + name + "\": " + m); };
  for (int i = 0; i < 3; ++i) {
    if (!InUnit(base_color[i])) fail("base_color must be in [0, 1]");
    if (!std::isfinite(emissive[i]) || emissive[i] < 0) fail("emissive must be finite and >= 0");
  }
  if (!InUnit(metallic)) fail("metallic must be in [0, 1]");
  if (!base_color_uv_transform.linear.allFinite() || !base_color_uv_transform.offset.allFinite()) {
    fail("base colour texture transform must be finite");
  }
  if (!InUnit(roughness)) fail("roughness must be in [0, 1]");
  if (!InUnit(alpha)) fail("alpha must be in [0, 1]");
  if (!std::isfinite(alpha_cutoff) || alpha_cutoff < 0) fail("alpha cutoff must be finite and >= 0");
  if (subsurface) {
    if (!(subsurface->mean_free_path_m.array() > 0).all() || !subsurface->mean_free_path_m.allFinite()) {
      fail("subsurface mean free path must be > 0");
    }
    if (!(subsurface->mean_free_path_laser_m > 0) || !std::isfinite(subsurface->mean_free_path_laser_m)) {
      fail("subsurface mean free path at the laser wavelength must be > 0");
    }
  }
}

Material DefaultMaterial() {
  Material m;
  m.name = "default";
  m.base_color = Eigen::Vector3f::Ones();
  m.metallic = 1;
  m.roughness = 1;
  return m;
}

}  // namespace lt

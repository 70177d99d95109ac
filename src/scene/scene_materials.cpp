#include "scene/scene_materials.h"

#include <variant>

#include "core/error.h"
#include "core/image_io.h"

namespace lt {

using json::Range;

namespace {

constexpr double kMm = 1e-3;

Subsurface ParseSubsurface(const json::Value& value) {
  json::Object o(value);
  Subsurface s;
  json::Value mfp = o.Get("mean_free_path_mm");
  if (mfp.IsArray()) {
    s.mean_free_path_m = mfp.Vec3(Range::Positive()) * kMm;
  } else if (mfp.IsNumber()) {
    s.mean_free_path_m = Eigen::Vector3d::Constant(mfp.Number(Range::Positive()) * kMm);
  } else {
    mfp.Fail("must be a number or an array of 3 numbers (red, green, blue)");
  }
  // Default: the red channel's value, which is where the common 635-660 nm lasers lie.
  s.mean_free_path_laser_m = o.Number("mean_free_path_laser_mm", s.mean_free_path_m.x() / kMm, Range::Positive()) * kMm;
  o.Finish();
  return s;
}

}  // namespace

std::shared_ptr<Texture> LoadTextureFile(const std::filesystem::path& path, const json::Value& value) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) value.Fail("texture not found (looked for " + path.string() + ")");
  AnyImage any;
  try {
    any = ReadImage(path);
  } catch (const InputError& e) {
    value.Fail(e.what());
  }
  auto tex = std::make_shared<Texture>();
  tex->name = path.string();
  auto fill = [&](const auto& img, auto to8) {
    tex->image = Image<uint8_t>(img.width, img.height, 4, 255);
    const int c = img.channels;
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        uint8_t* out = &tex->image.At(x, y, 0);
        if (c <= 2) {
          out[0] = out[1] = out[2] = to8(img.At(x, y, 0));
          if (c == 2) out[3] = to8(img.At(x, y, 1));
        } else {
          for (int k = 0; k < 3; ++k) out[k] = to8(img.At(x, y, k));
          if (c >= 4) out[3] = to8(img.At(x, y, 3));
        }
      }
    }
  };
  if (auto* i8 = std::get_if<Image<uint8_t>>(&any)) {
    fill(*i8, [](uint8_t v) { return v; });
  } else if (auto* i16 = std::get_if<Image<uint16_t>>(&any)) {
    fill(*i16, [](uint16_t v) { return uint8_t((uint32_t(v) + 128) / 257); });
  } else {
    value.Fail("texture must be an 8- or 16-bit image (PNG, JPEG, TIFF), got a float image: " + path.string());
  }
  return tex;
}

std::vector<SceneMaterial> ParseSceneMaterials(const json::Value& value) {
  json::Object all(value);
  std::vector<SceneMaterial> out;
  for (auto it = value.raw().begin(); it != value.raw().end(); ++it) {
    const std::string name = it.key();
    json::Value mv = all.Get(name);
    if (name.empty()) mv.Fail("material names must not be empty");
    json::Object o(mv);
    SceneMaterial sm;
    Material& m = sm.material;
    m.name = name;
    m.base_color = o.Vec3("base_color", Eigen::Vector3d::Constant(0.8), Range::Closed(0, 1)).cast<float>();
    if (auto tex = o.Find("base_color_texture")) {
      sm.base_color_texture_path = tex->ExistingFile("texture");
      m.base_color_texture = LoadTextureFile(sm.base_color_texture_path, *tex);
    }
    m.metallic = float(o.Number("metallic", 0.0, Range::Closed(0, 1)));
    m.roughness = float(o.Number("roughness", 0.5, Range::Closed(0, 1)));
    m.emissive = o.Vec3("emissive", Eigen::Vector3d::Zero(), Range::NonNegative()).cast<float>();
    m.double_sided = o.Bool("double_sided", false);
    if (auto ss = o.Find("subsurface")) m.subsurface = ParseSubsurface(*ss);
    o.Finish();
    out.push_back(std::move(sm));
  }
  all.Finish();
  return out;
}

}  // namespace lt

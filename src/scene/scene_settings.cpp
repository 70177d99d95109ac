#include "scene/scene_settings.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include "core/error.h"
#include "core/image_io.h"

namespace lt {

using json::Range;

namespace {

// OpenEXR files begin with the magic number 20000630 (little endian).
bool IsOpenExrFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char magic[4] = {};
  in.read(reinterpret_cast<char*>(magic), 4);
  return in.gcount() == 4 && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01;
}

}  // namespace

void RenderSettings::Check() const {
  if (spp < 1 || spp > 65536) throw std::invalid_argument("render.spp must be in [1, 65536]");
  if (!(adaptive_noise >= 0 && adaptive_noise <= 10)) throw std::invalid_argument("render.adaptive_noise must be in [0, 10]");
  if (edge_spp_factor < 1 || edge_spp_factor > 64) throw std::invalid_argument("render.edge_spp_factor must be in [1, 64]");
  if (light_paths < 0 || light_paths > 65536) throw std::invalid_argument("render.light_paths must be in [0, 65536]");
  if (max_bounces < 0 || max_bounces > 64) throw std::invalid_argument("render.max_bounces must be in [0, 64]");
  if (russian_roulette_depth < 1 || russian_roulette_depth > 64) {
    throw std::invalid_argument("render.russian_roulette_depth must be in [1, 64]");
  }
  if (threads < 0 || threads > 1024) throw std::invalid_argument("render.threads must be in [0, 1024]");
  if (frames < 1 || frames > 1000000) throw std::invalid_argument("render.frames must be in [1, 1000000]");
  if (!(speckle_contrast >= 0 && speckle_contrast <= 1)) {
    throw std::invalid_argument("render.speckle_contrast must be in [0, 1]");
  }
}

void OutputSettings::Check() const {
  if (png_bit_depth != 8 && png_bit_depth != 16) throw std::invalid_argument("output.png_bit_depth must be 8 or 16");
}

void Environment::Check() const {
  if (!radiance.allFinite() || (radiance.array() < 0).any()) {
    throw std::invalid_argument("environment radiance must be finite and >= 0");
  }
  if (!std::isfinite(scale) || scale < 0) throw std::invalid_argument("environment scale must be >= 0");
  if (kind == Kind::kMap && exr.empty()) throw std::invalid_argument("environment map path is empty");
}

RenderSettings ParseRenderSettings(const json::Value& value) {
  json::Object o(value);
  RenderSettings s;
  s.spp = int(o.Integer("spp", s.spp, Range::Closed(1, 65536)));
  s.max_bounces = int(o.Integer("max_bounces", s.max_bounces, Range::Closed(0, 64)));
  s.russian_roulette_depth = int(o.Integer("russian_roulette_depth", s.russian_roulette_depth, Range::Closed(1, 64)));
  s.adaptive_sampling = o.Bool("adaptive_sampling", s.adaptive_sampling);
  s.adaptive_noise = o.Number("adaptive_noise", s.adaptive_noise, Range::Closed(0, 10));
  s.edge_spp_factor = int(o.Integer("edge_spp_factor", s.edge_spp_factor, Range::Closed(1, 64)));
  s.light_paths = int(o.Integer("light_paths", s.light_paths, Range::Closed(0, 65536)));
  s.subsurface = o.Bool("subsurface", s.subsurface);
  s.subsurface_cache = o.Bool("subsurface_cache", s.subsurface_cache);
  s.threads = int(o.Integer("threads", s.threads, Range::Closed(0, 1024)));
  s.frames = int(o.Integer("frames", s.frames, Range::Closed(1, 1000000)));
  s.speckle_contrast = o.Number("speckle_contrast", s.speckle_contrast, Range::Closed(0, 1));
  o.Finish();
  return s;
}

OutputSettings ParseOutputSettings(const json::Value& value) {
  json::Object o(value);
  OutputSettings s;
  if (auto v = o.Find("png_bit_depth")) {
    s.png_bit_depth = int(v->Integer());
    if (s.png_bit_depth != 8 && s.png_bit_depth != 16) {
      v->Fail("must be 8 or 16, got " + std::to_string(v->Integer()));
    }
  }
  s.write_radiance = o.Bool("write_radiance", s.write_radiance);
  s.write_ground_truth = o.Bool("write_ground_truth", s.write_ground_truth);
  o.Finish();
  return s;
}

Environment ParseEnvironment(const json::Value& value) {
  json::Object o(value);
  Environment e;
  bool has_radiance = o.Has("radiance"), has_exr = o.Has("exr");
  if (has_radiance == has_exr) o.Fail("give exactly one of \"radiance\" (constant) or \"exr\" (map)");
  if (has_radiance) {
    e.kind = Environment::Kind::kConstant;
    e.radiance = o.Vec3("radiance", Range::NonNegative());
  } else {
    e.kind = Environment::Kind::kMap;
    json::Value exr = o.Get("exr");
    e.exr = exr.ExistingFile("environment map");
    if (!IsOpenExrFile(e.exr)) exr.Fail(e.exr.string() + " is not an OpenEXR file");
    // Read now, so that `info` sees what the renderer would refuse, and a NaN, an
    // infinity or a negative value (radiance) is named instead of spreading
    // through the frames.
    auto map = std::make_shared<Image<float>>();
    try {
      *map = ReadImageFloat(e.exr);
    } catch (const InputError& err) {
      exr.Fail(err.what());
    }
    for (size_t i = 0; i < map->pixels.size(); ++i) {
      const float v = map->pixels[i];
      if (std::isfinite(v) && v >= 0) continue;
      const size_t c = size_t(map->channels), w = size_t(map->width);
      exr.Fail(e.exr.string() + ": pixel (" + std::to_string(i / c % w) + ", " + std::to_string(i / c / w) +
               ") channel " + std::to_string(i % c) + " is " + FormatNumber(v) +
               "; an environment map holds radiance, finite and >= 0");
    }
    e.map = std::move(map);
    e.scale = o.Number("scale", 1.0, Range::NonNegative());
  }
  o.Finish();
  return e;
}

nlohmann::json ToJson(const RenderSettings& s) {
  return {{"spp", s.spp},
          {"max_bounces", s.max_bounces},
          {"russian_roulette_depth", s.russian_roulette_depth},
          {"adaptive_sampling", s.adaptive_sampling},
          {"adaptive_noise", s.adaptive_noise},
          {"edge_spp_factor", s.edge_spp_factor},
          {"light_paths", s.light_paths},
          {"subsurface", s.subsurface},
          {"subsurface_cache", s.subsurface_cache},
          {"threads", s.threads},
          {"frames", s.frames},
          {"speckle_contrast", s.speckle_contrast}};
}

nlohmann::json ToJson(const OutputSettings& s) {
  return {{"png_bit_depth", s.png_bit_depth},
          {"write_radiance", s.write_radiance},
          {"write_ground_truth", s.write_ground_truth}};
}

nlohmann::json ToJson(const Environment& e) {
  if (e.kind == Environment::Kind::kMap) return {{"exr", e.exr.string()}, {"scale", e.scale}};
  return {{"radiance", {e.radiance.x(), e.radiance.y(), e.radiance.z()}}};
}

}  // namespace lt

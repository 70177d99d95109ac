// The small sections of a scene file: render settings, outputs and environment
// lighting. Each has defaults (a missing section means all defaults), a parser
// that rejects unknown keys and out-of-range values, and a JSON writer with every
// key filled in (for the resolved scene.json of a run).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/json_reader.h"

namespace lt {

struct RenderSettings {
  int spp = 16;                    // samples per pixel, [1, 65536]
  int max_bounces = 2;             // indirect bounces after the first hit, [0, 64]
  int russian_roulette_depth = 3;  // bounce from which paths may be cut short, [1, 64]
  bool adaptive_sampling = true;   // pixels no light path can reach get one sample
  // With adaptive_sampling: a pixel stops taking samples once the Monte Carlo
  // standard error of its mean is below this fraction of the sensor's temporal
  // noise at its signal, [0, 10]; 0 = every sampled pixel takes spp samples.
  double adaptive_noise = 0.25;
  // With adaptive_sampling, in frames lit only by the lasers: pixels in a laser
  // beam near a geometric edge (a crease or a step between neighbouring pixels'
  // surfaces) take this many times spp samples, [1, 64]; 1 = no more than spp.
  int edge_spp_factor = 8;
  // In frames where the scanner holds still: light paths per laser sheet and per
  // spp that carry laser light reflected on from grazing incidence
  // (render/path_tracer_light_paths.cpp), [0, 65536]; 0 = camera paths carry it.
  int light_paths = 4096;
  bool subsurface = true;          // false renders subsurface materials as surfaces only
  // Laser light entering subsurface materials from a per-frame cache of the lit
  // surface (render/laser_entry_tree.h) where the frame allows; false: Monte Carlo everywhere.
  bool subsurface_cache = true;
  int threads = 0;                 // 0 = all hardware threads, else [1, 1024]
  int frames = 1;                  // frames in the sequence, [1, 1000000]
  double speckle_contrast = 0;     // laser speckle contrast C in [0, 1]; 0 = no speckle
  void Check() const;              // throws std::invalid_argument
};

struct OutputSettings {
  int png_bit_depth = 8;           // 8 or 16
  bool write_radiance = true;      // radiance/ EXR beside each frame
  bool write_ground_truth = true;  // gt/ EXR buffers beside each frame
  void Check() const;
};

// Light arriving from far away, in linear RGB radiance W/(m^2 sr) per channel.
struct Environment {
  enum class Kind { kConstant, kMap };
  Kind kind = Kind::kConstant;
  Eigen::Vector3d radiance = Eigen::Vector3d::Zero();  // kConstant, >= 0
  std::filesystem::path exr;                           // kMap: lat-long OpenEXR map
  double scale = 1.0;                                  // kMap: multiplies the map, >= 0
  // kMap: the map as ParseEnvironment read and checked it (every value finite and
  // >= 0), or null (an Environment made in code: the renderer reads `exr`).
  std::shared_ptr<const Image<float>> map;
  void Check() const;
};

RenderSettings ParseRenderSettings(const json::Value& value);
OutputSettings ParseOutputSettings(const json::Value& value);
// Reads an environment map and checks it: the file exists (the message names the
// path looked for), decodes, and holds radiance (every value finite and >= 0; the
// message names the first pixel that is not).
Environment ParseEnvironment(const json::Value& value);

nlohmann::json ToJson(const RenderSettings& s);
nlohmann::json ToJson(const OutputSettings& s);
nlohmann::json ToJson(const Environment& e);

}  // namespace lt

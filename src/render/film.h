// Per-pixel accumulation of the renderer's samples: broadband RGB radiance,
// laser radiance per laser sheet (so that the laser-only image and the sheet
// that dominates each pixel can be written), sample counts, and a running
// (Welford) variance of one scalar per pixel for adaptive sampling.
//
// Plain float arrays, no locks: each pixel must be written by one thread at a
// time, as when tiles own disjoint pixels. The result for a pixel depends only
// on the order of its own samples, so it is the same whatever the tiling or
// thread count.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/image.h"

namespace lt {

struct FilmOptions {
  int width = 0;
  int height = 0;
  int laser_sheets = 0;  // laser radiance channels, one per sheet (>= 0)
  // The scalar whose variance is tracked: v = rgb_weights . rgb + laser_weight * sum(laser).
  // Defaults: Rec. 709 luminance, and laser radiance as is; a renderer may use
  // the camera's response per channel and at the laser wavelength instead.
  Eigen::Vector3f rgb_weights = Eigen::Vector3f(0.2126f, 0.7152f, 0.0722f);
  float laser_weight = 1.0f;

  // Throws lt::InputError(where, ...) for a negative or empty size or negative sheet count.
  void Check(const std::string& where) const;
};

class Film {
 public:
  explicit Film(const FilmOptions& options);  // calls options.Check("film")

  int width() const { return options_.width; }
  int height() const { return options_.height; }
  int laser_sheets() const { return options_.laser_sheets; }

  // Adds one sample to pixel (x, y): radiance rgb [W/(m^2 sr) per channel]
  // and the laser radiance of each sheet (laser.size() == laser_sheets()).
  void AddSample(int x, int y, const Eigen::Vector3f& rgb, std::span<const float> laser);

  uint32_t SampleCount(int x, int y) const { return count_[Index(x, y)]; }
  // Means over the pixel's samples (zero before the first).
  Eigen::Vector3f MeanRgb(int x, int y) const;
  float MeanLaser(int x, int y, int sheet) const;
  float MeanLaserTotal(int x, int y) const;
  // Sheet with the largest mean laser radiance in the pixel; -1 when none is > 0.
  int DominantSheet(int x, int y) const;

  // Tracked scalar v: its mean, its sample variance (n - 1 denominator; 0 for
  // fewer than 2 samples), and the standard error of the mean relative to
  // max(|mean|, floor) (floor > 0 keeps dark pixels from demanding samples).
  float MeanValue(int x, int y) const { return mean_[Index(x, y)]; }
  float Variance(int x, int y) const;
  float RelativeStandardError(int x, int y, float floor) const;

  // Whole-image views of the means: RGB (3 channels), total laser, one
  // sheet's laser, the dominant sheet (-1 where unlit), the sample counts.
  Image<float> RgbImage() const;
  Image<float> LaserImage() const;
  Image<float> LaserSheetImage(int sheet) const;
  Image<int32_t> DominantSheetImage() const;
  Image<uint32_t> SampleCountImage() const;

  void Clear();

 private:
  size_t Index(int x, int y) const { return size_t(y) * size_t(options_.width) + size_t(x); }

  FilmOptions options_;
  std::vector<float> rgb_sum_;    // 3 per pixel
  std::vector<float> laser_sum_;  // laser_sheets per pixel
  std::vector<uint32_t> count_;
  std::vector<float> mean_;       // Welford running mean of v
  std::vector<float> m2_;         // Welford sum of squared deviations of v
};

}  // namespace lt

#include "render/film.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>

#include "core/error.h"

namespace lt {

void FilmOptions::Check(const std::string& where) const {
  if (width <= 0 || height <= 0) {
    throw InputError(where, "image size must be at least 1 x 1, got " + std::to_string(width) + " x " +
                                std::to_string(height));
  }
  if (laser_sheets < 0) throw InputError(where, "laser sheet count must be >= 0, got " + std::to_string(laser_sheets));
  if (!rgb_weights.allFinite() || !std::isfinite(laser_weight)) {
    throw InputError(where, "variance weights must be finite");
  }
}

Film::Film(const FilmOptions& options) : options_(options) {
  options_.Check("film");
  const size_t n = size_t(options_.width) * size_t(options_.height);
  rgb_sum_.assign(3 * n, 0.0f);
  laser_sum_.assign(size_t(options_.laser_sheets) * n, 0.0f);
  count_.assign(n, 0);
  mean_.assign(n, 0.0f);
  m2_.assign(n, 0.0f);
}

void Film::Clear() {
  std::fill(rgb_sum_.begin(), rgb_sum_.end(), 0.0f);
  std::fill(laser_sum_.begin(), laser_sum_.end(), 0.0f);
  std::fill(count_.begin(), count_.end(), 0u);
  std::fill(mean_.begin(), mean_.end(), 0.0f);
  std::fill(m2_.begin(), m2_.end(), 0.0f);
}

void Film::AddSample(int x, int y, const Eigen::Vector3f& rgb, std::span<const float> laser) {
  assert(x >= 0 && x < options_.width && y >= 0 && y < options_.height);
  if (laser.size() != size_t(options_.laser_sheets)) {
    throw std::invalid_argument("Film::AddSample: laser sample has the wrong number of sheets");
  }
  const size_t i = Index(x, y);
  float* rgb_sum = &rgb_sum_[3 * i];
  rgb_sum[0] += rgb.x();
  rgb_sum[1] += rgb.y();
  rgb_sum[2] += rgb.z();
  float laser_total = 0.0f;
  float* laser_sum = laser_sum_.data() + i * laser.size();
  for (size_t s = 0; s < laser.size(); ++s) {
    laser_sum[s] += laser[s];
    laser_total += laser[s];
  }
  // Welford's update of the running mean and squared deviations.
  const float v = options_.rgb_weights.dot(rgb) + options_.laser_weight * laser_total;
  const uint32_t n = ++count_[i];
  const float delta = v - mean_[i];
  mean_[i] += delta / float(n);
  m2_[i] += delta * (v - mean_[i]);
}

Eigen::Vector3f Film::MeanRgb(int x, int y) const {
  const size_t i = Index(x, y);
  if (count_[i] == 0) return Eigen::Vector3f::Zero();
  return Eigen::Vector3f(rgb_sum_[3 * i], rgb_sum_[3 * i + 1], rgb_sum_[3 * i + 2]) / float(count_[i]);
}

float Film::MeanLaser(int x, int y, int sheet) const {
  assert(sheet >= 0 && sheet < options_.laser_sheets);
  const size_t i = Index(x, y);
  if (count_[i] == 0) return 0.0f;
  return laser_sum_[i * size_t(options_.laser_sheets) + size_t(sheet)] / float(count_[i]);
}

float Film::MeanLaserTotal(int x, int y) const {
  float total = 0.0f;
  for (int s = 0; s < options_.laser_sheets; ++s) total += MeanLaser(x, y, s);
  return total;
}

int Film::DominantSheet(int x, int y) const {
  const size_t i = Index(x, y);
  int best = -1;
  float best_value = 0.0f;
  for (int s = 0; s < options_.laser_sheets; ++s) {
    const float v = laser_sum_[i * size_t(options_.laser_sheets) + size_t(s)];
    if (v > best_value) {
      best_value = v;
      best = s;
    }
  }
  return best;
}

float Film::Variance(int x, int y) const {
  const size_t i = Index(x, y);
  return count_[i] < 2 ? 0.0f : std::max(0.0f, m2_[i]) / float(count_[i] - 1);
}

float Film::RelativeStandardError(int x, int y, float floor) const {
  const size_t i = Index(x, y);
  if (count_[i] == 0) return INFINITY;
  const float standard_error = std::sqrt(Variance(x, y) / float(count_[i]));
  return standard_error / std::max(std::abs(mean_[i]), floor);
}

Image<float> Film::RgbImage() const {
  Image<float> im(options_.width, options_.height, 3);
  for (int y = 0; y < options_.height; ++y) {
    for (int x = 0; x < options_.width; ++x) {
      const Eigen::Vector3f m = MeanRgb(x, y);
      for (int c = 0; c < 3; ++c) im.At(x, y, c) = m[c];
    }
  }
  return im;
}

Image<float> Film::LaserImage() const {
  Image<float> im(options_.width, options_.height, 1);
  for (int y = 0; y < options_.height; ++y) {
    for (int x = 0; x < options_.width; ++x) im.At(x, y) = MeanLaserTotal(x, y);
  }
  return im;
}

Image<float> Film::LaserSheetImage(int sheet) const {
  if (sheet < 0 || sheet >= options_.laser_sheets) throw std::out_of_range("Film::LaserSheetImage: no such sheet");
  Image<float> im(options_.width, options_.height, 1);
  for (int y = 0; y < options_.height; ++y) {
    for (int x = 0; x < options_.width; ++x) im.At(x, y) = MeanLaser(x, y, sheet);
  }
  return im;
}

Image<int32_t> Film::DominantSheetImage() const {
  Image<int32_t> im(options_.width, options_.height, 1);
  for (int y = 0; y < options_.height; ++y) {
    for (int x = 0; x < options_.width; ++x) im.At(x, y) = DominantSheet(x, y);
  }
  return im;
}

Image<uint32_t> Film::SampleCountImage() const {
  Image<uint32_t> im(options_.width, options_.height, 1);
  im.pixels = count_;
  return im;
}

}  // namespace lt

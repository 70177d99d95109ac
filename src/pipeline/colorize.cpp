#include "pipeline/colorize.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <type_traits>

#include "core/error.h"
#include "core/image_io.h"

namespace lt {

namespace {

// Bilinear interpolation of channel `c` of `image` over the pixels (x0 + 2i, y0 + 2j)
// (step 2, a Bayer colour's lattice) or every pixel (step 1).
double Bilinear(const Image<float>& image, int c, double u, double v, int x0, int y0, int step) {
  const int nx = (image.width - x0 + step - 1) / step, ny = (image.height - y0 + step - 1) / step;
  if (nx <= 0 || ny <= 0) return 0;
  const double gx = std::clamp((u - x0) / step, 0.0, double(nx - 1));
  const double gy = std::clamp((v - y0) / step, 0.0, double(ny - 1));
  const int ix = std::min(int(gx), std::max(nx - 2, 0)), iy = std::min(int(gy), std::max(ny - 2, 0));
  const double fx = gx - ix, fy = gy - iy;
  auto at = [&](int i, int j) {
    i = std::min(i, nx - 1);
    j = std::min(j, ny - 1);
    return double(image.At(x0 + step * i, y0 + step * j, c));
  };
  return (1 - fy) * ((1 - fx) * at(ix, iy) + fx * at(ix + 1, iy)) + fy * ((1 - fx) * at(ix, iy + 1) + fx * at(ix + 1, iy + 1));
}

}  // namespace

void ColourOptions::Check() const {
  if (!(std::isfinite(contamination_ratio) && contamination_ratio > 0)) {
    throw InputError("option contamination-ratio", "must be > 0, got " + FormatNumber(contamination_ratio));
  }
}

Eigen::Vector3d SampleColour(const Image<float>& image, ColorFilter filter, const Eigen::Vector2d& uv) {
  if (image.empty()) return Eigen::Vector3d::Zero();
  if (image.channels >= 3) {
    return {Bilinear(image, 0, uv.x(), uv.y(), 0, 0, 1), Bilinear(image, 1, uv.x(), uv.y(), 0, 0, 1),
            Bilinear(image, 2, uv.x(), uv.y(), 0, 0, 1)};
  }
  if (filter == ColorFilter::kMono) return Eigen::Vector3d::Constant(Bilinear(image, 0, uv.x(), uv.y(), 0, 0, 1));
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), count = Eigen::Vector3d::Zero();
  for (int y0 = 0; y0 < 2; ++y0) {
    for (int x0 = 0; x0 < 2; ++x0) {
      const int c = FilterChannel(filter, x0, y0);
      sum[c] += Bilinear(image, 0, uv.x(), uv.y(), x0, y0, 2);
      count[c] += 1;
    }
  }
  return sum.cwiseQuotient(count);
}

struct Colorizer::Bright {
  Pose cam_from_world;
  Image<float> image;     // the camera image, in its own units
  double full_scale = 1;  // of the image's values
  double black = 0;       // black level in the image's units
  Image<float> radiance;  // R, G, B, laser; empty without a radiance EXR
  double laser_fraction = 0;
};

Colorizer::Colorizer(const std::vector<RunFrame>& frames, const Camera& camera, ColorFilter filter,
                     double black_level_dn, const ColourOptions& options)
    : frames_(frames), camera_(camera), filter_(filter), black_level_dn_(black_level_dn), options_(options) {
  options_.Check();
}

Colorizer::~Colorizer() = default;

const Colorizer::Bright* Colorizer::Load(size_t position) {
  auto it = cache_.find(position);
  if (it != cache_.end()) return it->second.get();
  // Frames come in order: drop bright frames well behind this one.
  while (!cache_.empty() && cache_.begin()->first + 4 < position) cache_.erase(cache_.begin());
  const RunFrame& f = frames_[position];
  auto b = std::make_unique<Bright>();
  b->cam_from_world = f.world_from_cam->inverse();
  b->laser_fraction = f.laser_fraction;
  const std::string context = " (bright frame " + std::to_string(f.index) + ", " + f.where + ")";
  AnyImage any;
  try {
    any = ReadImage(f.image, AlphaChannel::kDrop);
  } catch (const InputError& e) {
    throw InputError(e.where(), e.message() + context);
  }
  std::visit(
      [&](const auto& im) {
        using T = std::decay_t<decltype(im.pixels[0])>;
        b->image = Image<float>(im.width, im.height, im.channels);
        for (size_t i = 0; i < im.pixels.size(); ++i) b->image.pixels[i] = float(im.pixels[i]);
        b->full_scale = f.FullScale(TypeFullScale<T>());
        double black = black_level_dn_;
        if (TypeFullScale<T>() == 255.0 && f.bit_depth > 8) black = std::ldexp(black, 8 - f.bit_depth);
        b->black = black;
      },
      any);
  if (b->image.width != camera_.width() || b->image.height != camera_.height()) {
    throw InputError(f.image.string(), "the image is " + std::to_string(b->image.width) + "x" +
                                           std::to_string(b->image.height) + " but the camera is " +
                                           std::to_string(camera_.width()) + "x" + std::to_string(camera_.height()) +
                                           context);
  }
  if (f.radiance) {
    try {
      b->radiance = ReadImageChannels(*f.radiance, {"R", "G", "B", "laser"});
    } catch (const InputError& e) {
      throw InputError(e.where(), e.message() + context);
    }
  }
  ++stats_.bright_frames;
  return cache_.emplace(position, std::move(b)).first->second.get();
}

std::vector<PointColour> Colorizer::Colour(int frame_index, const std::vector<Eigen::Vector3d>& points_in_world) {
  std::vector<PointColour> out(points_in_world.size());
  stats_.points += int(points_in_world.size());
  // The bright frames before and after this frame.
  // Laser and pattern frames are passed over: the nearest flood-lit frame each side.
  auto is_bright = [](const RunFrame& f) { return f.IsColourFrame() && f.world_from_cam.has_value(); };
  size_t here = frames_.size();
  for (size_t i = 0; i < frames_.size(); ++i) {
    if (frames_[i].index == frame_index) here = i;
  }
  if (here == frames_.size()) return out;
  std::vector<size_t> sources;
  for (size_t i = here; i-- > 0;) {
    if (!frames_[i].IsColourFrame()) continue;
    if (is_bright(frames_[i])) sources.push_back(i);
    break;
  }
  for (size_t i = here + 1; i < frames_.size(); ++i) {
    if (!frames_[i].IsColourFrame()) continue;
    if (is_bright(frames_[i])) sources.push_back(i);
    break;
  }
  std::vector<Eigen::Vector3d> sum(points_in_world.size(), Eigen::Vector3d::Zero());
  std::vector<int> count(points_in_world.size(), 0);
  for (size_t s : sources) {
    const Bright* b = Load(s);
    if (b->radiance.empty()) stats_.from_radiance = false;
    for (size_t k = 0; k < points_in_world.size(); ++k) {
      const Eigen::Vector3d p_cam = b->cam_from_world * points_in_world[k];
      if (!(p_cam.z() > 0)) continue;
      auto uv = camera_.Project(p_cam);
      if (!uv || uv->x() < -0.5 || uv->y() < -0.5 || uv->x() > camera_.width() - 0.5 ||
          uv->y() > camera_.height() - 0.5) {
        continue;
      }
      const Eigen::Vector3d dn = SampleColour(b->image, filter_, *uv);
      sum[k] += ((dn.array() - b->black) / std::max(b->full_scale - b->black, 1e-12)).matrix();
      ++count[k];
      bool lit;
      if (!b->radiance.empty()) {
        const Eigen::Vector3d rgb = SampleColour(b->radiance, ColorFilter::kMono, *uv);  // channels 0..2
        const int x = std::clamp(int(std::lround(uv->x())), 0, b->radiance.width - 1);
        const int y = std::clamp(int(std::lround(uv->y())), 0, b->radiance.height - 1);
        const double laser = b->radiance.At(x, y, 3);
        lit = laser > 0 && laser >= options_.contamination_ratio * rgb.mean();
      } else {
        lit = b->laser_fraction > 0;
      }
      out[k].contaminated |= lit;
    }
  }
  for (size_t k = 0; k < out.size(); ++k) {
    if (count[k] == 0) {
      out[k].contaminated = false;
      continue;
    }
    const Eigen::Vector3d c = sum[k] / count[k];
    for (int i = 0; i < 3; ++i) out[k].rgb[size_t(i)] = uint8_t(std::lround(std::clamp(c[i], 0.0, 1.0) * 255.0));
    out[k].coloured = true;
    ++stats_.coloured;
    stats_.contaminated += out[k].contaminated;
  }
  return out;
}

}  // namespace lt

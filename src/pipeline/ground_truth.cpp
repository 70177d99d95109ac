#include "pipeline/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/image_io.h"
#include "core/text_fields.h"

namespace lt {

namespace {

constexpr const char* kTruthHeader = "u,v,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world";

}  // namespace

std::vector<TruthCenter> ReadTruthCentersCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), std::filesystem::exists(path) ? "cannot open" : "no such file");
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != kTruthHeader) throw InputError(path.string() + ":1", std::string("expected the header ") + kTruthHeader);
  std::vector<TruthCenter> centers;
  for (int line_no = 2; std::getline(in, line); ++line_no) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::string where = path.string() + ":" + std::to_string(line_no);
    const std::vector<std::string_view> f = SplitFields(line, ',');
    if (f.size() != 9) throw InputError(where, "expected 9 fields, got " + std::to_string(f.size()));
    double v[6];
    for (size_t k = 0; k < 6; ++k) v[k] = FiniteField(f, k, where);
    if (v[2] != std::floor(v[2]) || v[2] < 0 || v[2] > 1e6) {
      throw InputError(where, "plane must be an integer >= 0, got '" + std::string(f[2]) + "'");
    }
    centers.push_back({v[0], v[1], int(v[2]), Eigen::Vector3d(v[3], v[4], v[5]), line_no});
  }
  return centers;
}

TrueSurface::TrueSurface(const Camera& camera, const std::filesystem::path& gt_exr) : camera_(camera) {
  std::vector<std::string> names;
  buffers_ = ReadImageFloat(gt_exr, &names);
  auto channel = [&](const std::string& name, bool required) {
    auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
      if (!required) return -1;
      throw InputError(gt_exr.string(), "no channel '" + name + "' (ground-truth buffers need Z, N.X, N.Y, N.Z)");
    }
    return int(it - names.begin());
  };
  z_ = channel("Z", true);
  nx_ = channel("N.X", true);
  ny_ = channel("N.Y", true);
  nz_ = channel("N.Z", true);
  instance_ = channel("instance", false);
  if (buffers_.width != camera.width() || buffers_.height != camera.height()) {
    throw InputError(gt_exr.string(), "the buffers are " + std::to_string(buffers_.width) + "x" +
                                          std::to_string(buffers_.height) + " but the camera is " +
                                          std::to_string(camera.width()) + "x" + std::to_string(camera.height()));
  }
}

TrueSurface::Texel TrueSurface::At(int x, int y) const {
  Texel t;
  const double z = buffers_.At(x, y, z_);
  const Eigen::Vector3d n(buffers_.At(x, y, nx_), buffers_.At(x, y, ny_), buffers_.At(x, y, nz_));
  const double norm = n.norm();
  if (!(z > 0) || !std::isfinite(z) || !(norm > 0.5) || !std::isfinite(norm)) return t;
  auto ray = camera_.Unproject({double(x), double(y)});
  if (!ray || !((*ray).z() > 0)) return t;
  t.hit = true;
  t.instance = instance_ >= 0 ? buffers_.At(x, y, instance_) : 0.0;
  t.s = (z / ray->z()) * *ray;
  t.n = n / norm;  // stored as half: renormalise
  return t;
}

std::optional<double> TrueSurface::SignedDistance(const Eigen::Vector3d& p_in_cam,
                                                  std::span<const Eigen::Vector3d> exact_points) const {
  if (!p_in_cam.allFinite()) return std::nullopt;
  auto pixel = camera_.Project(p_in_cam);
  if (!pixel || !camera_.InImage(*pixel)) return std::nullopt;
  const int w = buffers_.width, h = buffers_.height;
  const int xn = std::clamp(int(std::lround(pixel->x())), 0, w - 1);
  const int yn = std::clamp(int(std::lround(pixel->y())), 0, h - 1);
  const Texel nearest = At(xn, yn);
  if (!nearest.hit) return std::nullopt;

  const double d_nearest = nearest.n.dot(p_in_cam - nearest.s);

  // One smooth surface: same instance as the nearest pixel, normal within 30
  // degrees of its normal, and off its tangent plane by less than 30 degrees as
  // seen from its surface point (a step is not).
  const double cos30 = std::cos(M_PI / 6), sin30 = 0.5;
  auto same_surface = [&](const Texel& t) {
    if (!t.hit || t.instance != nearest.instance || t.n.dot(nearest.n) < cos30) return false;
    const Eigen::Vector3d step = t.s - nearest.s;
    return std::abs(nearest.n.dot(step)) <= sin30 * step.norm();
  };
  // A stripe point's light may come from anywhere within the nearest pixel.
  // Where the 3x3 pixels around it see a break (an edge, a step, a silhouette),
  // the light may be another surface's than the one the pixel's centre sees:
  // the distance to the nearest of the surfaces they see (their tangent
  // planes), as a cloud-to-mesh distance takes it, or to the nearest exact
  // surface point given (a face narrower than a pixel, a slot wall seen edge-on,
  // lies between pixel centres: no pixel sees it, its exact stripe centres do).
  double nearest_of_all = d_nearest;
  bool one_surface = true;
  for (int y = std::max(0, yn - 1); y <= std::min(h - 1, yn + 1); ++y)
    for (int x = std::max(0, xn - 1); x <= std::min(w - 1, xn + 1); ++x) {
      const Texel t = At(x, y);
      one_surface = one_surface && same_surface(t);
      if (!t.hit) continue;
      const double d = t.n.dot(p_in_cam - t.s);
      if (std::abs(d) < std::abs(nearest_of_all)) nearest_of_all = d;
    }
  if (!one_surface) {
    const Eigen::Vector3d toward_camera = -p_in_cam.normalized();
    for (const Eigen::Vector3d& q : exact_points) {
      const double d = (p_in_cam - q).norm();
      if (d < std::abs(nearest_of_all)) nearest_of_all = toward_camera.dot(p_in_cam - q) >= 0 ? d : -d;
    }
    return nearest_of_all;
  }

  // Bilinear over the 4 pixels around the projection (within those 3x3).
  const int x0 = int(std::floor(pixel->x())), y0 = int(std::floor(pixel->y()));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) return d_nearest;
  // Each pixel's distance is taken along the mean of its normal and the normal
  // at p (the 4 normals blended): on a curved surface the chord from a surface
  // point S to a surface point P is perpendicular to (n_S + n_P) exactly on a
  // sphere or cylinder, and to second order on any smooth surface, where the
  // tangent plane at S alone puts P |P - S|^2 / (2 R) away (0.026 mm for a
  // perfect measurement near a 4 mm cylinder's limb, where a pixel's footprint
  // on the surface is long). On a plane the normals are equal: nothing changes.
  const double fx = pixel->x() - x0, fy = pixel->y() - y0;
  Texel texels[4];
  double weights[4];
  Eigen::Vector3d n_p = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) {
    const int dx = k & 1, dy = k >> 1;
    texels[k] = At(x0 + dx, y0 + dy);
    weights[k] = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
    n_p += weights[k] * texels[k].n;
  }
  n_p.normalize();  // the normals are within 30 degrees of each other: no cancellation
  double blend = 0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d n_mean = (texels[k].n + n_p).normalized();
    blend += weights[k] * n_mean.dot(p_in_cam - texels[k].s);
  }
  return blend;
}

}  // namespace lt

#include "pipeline/calib_checkerboard.h"

#include <cmath>

#include "core/error.h"
#include "pipeline/option_checks.h"
#include "core/random.h"

namespace lt {

namespace {

constexpr uint64_t kJitterPurpose = 0x6a6974ull;  // "jit"
constexpr uint64_t kNoisePurpose = 0x6e6f6973ull;  // "nois"

}  // namespace

void CheckerboardSpec::Check() const {
  Require(rows >= 2, "rows", "must be >= 2 inner corners, got " + std::to_string(rows));
  Require(cols >= 2, "cols", "must be >= 2 inner corners, got " + std::to_string(cols));
  Require(std::isfinite(square_m) && square_m > 0, "square_m", "must be > 0, got " + FormatNumber(square_m));
  Require(margin_squares >= 0, "margin_squares", "must be >= 0, got " + std::to_string(margin_squares));
}

std::vector<Eigen::Vector3d> CheckerboardSpec::CornerPoints() const {
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(size_t(rows) * size_t(cols));
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) pts.emplace_back(j * square_m, i * square_m, 0.0);
  return pts;
}

int CheckerboardSpec::ColourAt(double x, double y) const {
  const double a = std::floor(x / square_m), b = std::floor(y / square_m);
  const double m = margin_squares;
  if (a < -1 - m || a > cols - 1 + m || b < -1 - m || b > rows - 1 + m) return -1;
  if (a < -1 || a > cols - 1 || b < -1 || b > rows - 1) return 1;
  return std::fmod(std::abs(a + b), 2.0) == 0 ? 0 : 1;
}

Image<float> RenderCheckerboard(const Camera& camera, const Pose& cam_from_board, const CheckerboardSpec& board,
                                const SyntheticBoardOptions& options) {
  board.Check();
  if (options.supersampling < 1) throw InputError("option supersampling", "must be >= 1");
  const int w = camera.width(), h = camera.height();
  // Scalar arithmetic throughout: this runs per pixel and per sample.
  const Eigen::Matrix3d rot = cam_from_board.linear();
  const Eigen::Vector3d tr = cam_from_board.translation();
  const double n0 = rot(0, 2), n1 = rot(1, 2), n2 = rot(2, 2);  // board normal, camera frame
  const double nt = n0 * tr.x() + n1 * tr.y() + n2 * tr.z();
  // Board (x, y) where the ray (dx, dy, dz) (any length) meets the board; false when it misses.
  auto ray_point = [&](double dx, double dy, double dz, double* bx, double* by) {
    const double denom = n0 * dx + n1 * dy + n2 * dz;
    if (std::abs(denom) < 1e-12 * std::sqrt(dx * dx + dy * dy + dz * dz)) return false;
    const double lambda = nt / denom;
    if (!(lambda > 0)) return false;
    const double px = lambda * dx - tr.x(), py = lambda * dy - tr.y(), pz = lambda * dz - tr.z();
    *bx = rot(0, 0) * px + rot(1, 0) * py + rot(2, 0) * pz;  // Rᵀ (p − t)
    *by = rot(0, 1) * px + rot(1, 1) * py + rot(2, 1) * pz;
    return true;
  };
  auto unproject_point = [&](double u, double v, double* bx, double* by) {
    const auto ray = camera.Unproject({u, v});
    return ray && ray_point(ray->x(), ray->y(), ray->z(), bx, by);
  };
  // Pixel corners: (x - 0.5, y - 0.5) for x in [0, w], y in [0, h]. Without
  // distortion the ray is direct; for Brown–Conrady the distortion is inverted
  // by Newton's method started from the previous corner of the row (two or
  // three steps), accepted when it reproduces the image point to 1e-10 px;
  // otherwise (and for the fisheye) Camera::Unproject.
  const size_t nc = size_t(w + 1) * size_t(h + 1);
  std::vector<double> cu(nc), cv(nc);
  std::vector<char> valid(nc);
  const DistortionModel model = camera.distortion_model();
  const BrownConradyCoeffs& bc = camera.distortion().brown_conrady();
  const double fx = camera.fx(), fy = camera.fy(), cx = camera.cx(), cy = camera.cy();
  for (int y = 0; y <= h; ++y) {
    double gx = NAN, gy = NAN;  // Newton's start: the previous corner's undistorted point
    for (int x = 0; x <= w; ++x) {
      const size_t k = size_t(y) * size_t(w + 1) + size_t(x);
      const double tx = (x - 0.5 - cx) / fx, ty = (y - 0.5 - cy) / fy;
      bool done = false;
      if (model == DistortionModel::kNone) {
        valid[k] = ray_point(tx, ty, 1.0, &cu[k], &cv[k]);
        done = true;
      } else if (model == DistortionModel::kBrownConrady && std::isfinite(gx)) {
        double xu = gx, yu = gy;
        for (int it = 0; it < 8; ++it) {
          const double r2 = xu * xu + yu * yu;
          const double radial = 1.0 + r2 * (bc.k1 + r2 * (bc.k2 + r2 * bc.k3));
          const double ex = xu * radial + 2.0 * bc.p1 * xu * yu + bc.p2 * (r2 + 2.0 * xu * xu) - tx;
          const double ey = yu * radial + bc.p1 * (r2 + 2.0 * yu * yu) + 2.0 * bc.p2 * xu * yu - ty;
          if (std::sqrt(ex * ex + ey * ey) * fx < 1e-10) {
            done = true;
            break;
          }
          const double g = 2.0 * bc.k1 + r2 * (4.0 * bc.k2 + 6.0 * bc.k3 * r2);
          const double cross = g * xu * yu + 2.0 * bc.p1 * xu + 2.0 * bc.p2 * yu;
          const double j00 = radial + g * xu * xu + 2.0 * bc.p1 * yu + 6.0 * bc.p2 * xu;
          const double j11 = radial + g * yu * yu + 6.0 * bc.p1 * yu + 2.0 * bc.p2 * xu;
          const double det = j00 * j11 - cross * cross;
          if (!(det > 0)) break;
          xu -= (j11 * ex - cross * ey) / det;
          yu -= (j00 * ey - cross * ex) / det;
        }
        if (done) {
          valid[k] = ray_point(xu, yu, 1.0, &cu[k], &cv[k]);
          gx = xu, gy = yu;
        }
      }
      if (!done) {
        const auto ray = camera.Unproject({x - 0.5, y - 0.5});
        valid[k] = ray && ray_point(ray->x(), ray->y(), ray->z(), &cu[k], &cv[k]);
        gx = ray && ray->z() > 0 ? ray->x() / ray->z() : NAN;
        gy = ray && ray->z() > 0 ? ray->y() / ray->z() : NAN;
      }
    }
  }
  const double s = board.square_m, m = board.margin_squares;
  const double x_min = -(1 + m) * s, x_max = (board.cols + m) * s, y_min = -(1 + m) * s, y_max = (board.rows + m) * s;
  auto value = [&](double bx, double by) {
    const int c = board.ColourAt(bx, by);
    return c < 0 ? options.background : c == 0 ? options.black : options.white;
  };
  Image<float> img(w, h, 1);
  const int ns = options.supersampling;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t k[4] = {size_t(y) * size_t(w + 1) + size_t(x), size_t(y) * size_t(w + 1) + size_t(x) + 1,
                           size_t(y + 1) * size_t(w + 1) + size_t(x), size_t(y + 1) * size_t(w + 1) + size_t(x) + 1};
      const bool all_valid = valid[k[0]] && valid[k[1]] && valid[k[2]] && valid[k[3]];
      if (all_valid) {
        bool uniform = true;
        const double u0 = cu[k[0]], v0 = cv[k[0]];
        if (u0 >= x_min && u0 < x_max && v0 >= y_min && v0 < y_max) {
          const double a0 = std::floor(u0 / s), b0 = std::floor(v0 / s);
          for (int q = 1; q < 4; ++q) {
            uniform = uniform && std::floor(cu[k[q]] / s) == a0 && std::floor(cv[k[q]] / s) == b0;
          }
        } else {
          // Off the board: uniform when all four corners lie beyond the same
          // side of the board's rectangle (the pixel is convex).
          bool left = true, right = true, above = true, below = true;
          for (int q = 0; q < 4; ++q) {
            left = left && cu[k[q]] < x_min;
            right = right && cu[k[q]] >= x_max;
            above = above && cv[k[q]] < y_min;
            below = below && cv[k[q]] >= y_max;
          }
          uniform = left || right || above || below;
        }
        if (uniform) {
          img.At(x, y) = float(value(u0, v0));
          continue;
        }
      }
      // Bilinear in the pixel: p = c0 + fa (c1 − c0) + fb (c2 − c0) + fa fb (c3 − c2 − c1 + c0).
      const double u0 = cu[k[0]], du_a = cu[k[1]] - u0, du_b = cu[k[2]] - u0, du_ab = cu[k[3]] - cu[k[2]] - cu[k[1]] + u0;
      const double v0 = cv[k[0]], dv_a = cv[k[1]] - v0, dv_b = cv[k[2]] - v0, dv_ab = cv[k[3]] - cv[k[2]] - cv[k[1]] + v0;
      Rng rng = Rng::For(options.seed, 0, uint64_t(y) * uint64_t(w) + uint64_t(x), 0, kJitterPurpose);
      double sum = 0;
      for (int b = 0; b < ns; ++b) {
        for (int a = 0; a < ns; ++a) {
          const double fa = (a + rng.NextDouble()) / ns, fb = (b + rng.NextDouble()) / ns;
          double bx, by;
          bool hit = true;
          if (all_valid) {
            bx = u0 + fa * du_a + fb * (du_b + fa * du_ab);
            by = v0 + fa * dv_a + fb * (dv_b + fa * dv_ab);
          } else {
            hit = unproject_point(x - 0.5 + fa, y - 0.5 + fb, &bx, &by);
          }
          sum += hit ? value(bx, by) : options.background;
        }
      }
      img.At(x, y) = float(sum / (ns * ns));
    }
  }
  if (options.noise_sigma > 0) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        Rng rng = Rng::For(options.seed, 0, uint64_t(y) * uint64_t(w) + uint64_t(x), 0, kNoisePurpose);
        img.At(x, y) += float(options.noise_sigma * rng.NextGaussian());
      }
  }
  return img;
}

}  // namespace lt

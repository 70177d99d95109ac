#include "pipeline/calib_checkerboard.h"

#include <cmath>

#include "core/error.h"
#include "core/random.h"

namespace lt {

namespace {

void Require(bool ok, const char* option, const std::string& message) {
  if (!ok) throw InputError(std::string("option ") + option, message);
}

constexpr uint64_t kJitterPurpose = 0x6a6974ull;  // "jit"
constexpr uint64_t kNoisePurpose = 0x6e6f6973ull;  // "nois"

}  // namespace

void CheckerboardSpec::Check() const {
  Require(rows >= 2, "rows", "must be >= 2 inner corners, got " + std::to_string(rows));
  Require(cols >= 2, "cols", "must be >= 2 inner corners, got " + std::to_string(cols));
  Require((rows + cols) % 2 == 1, "rows",
          "rows + cols must be odd (one even, one odd) so that the board's orientation is unambiguous, got " +
              std::to_string(rows) + " x " + std::to_string(cols));
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
  const Pose board_from_cam = cam_from_board.inverse();
  const Eigen::Vector3d n = cam_from_board.linear().col(2), t = cam_from_board.translation();
  // Board point of a ray (camera frame); false when it misses.
  auto ray_point = [&](const Eigen::Vector3d& ray, Eigen::Vector2d* out) {
    const double denom = n.dot(ray);
    if (std::abs(denom) < 1e-12) return false;
    const double lambda = n.dot(t) / denom;
    if (!(lambda > 0)) return false;
    *out = (board_from_cam * (lambda * ray)).head<2>();
    return true;
  };
  // Pixel corners: (x - 0.5, y - 0.5) for x in [0, w], y in [0, h]. For
  // Brown–Conrady the distortion is inverted by Newton's method started from
  // the previous corner of the row (two or three steps), accepted when it
  // reproduces the image point to 1e-10 px; otherwise Camera::Unproject.
  std::vector<Eigen::Vector2d> corner(size_t(w + 1) * size_t(h + 1));
  std::vector<char> valid(corner.size());
  const bool bc = camera.distortion_model() == DistortionModel::kBrownConrady;
  const BrownConradyCoeffs& coeffs = camera.distortion().brown_conrady();
  for (int y = 0; y <= h; ++y) {
    Eigen::Vector2d guess(NAN, NAN);
    for (int x = 0; x <= w; ++x) {
      const size_t k = size_t(y) * size_t(w + 1) + size_t(x);
      const Eigen::Vector2d target((x - 0.5 - camera.cx()) / camera.fx(), (y - 0.5 - camera.cy()) / camera.fy());
      bool done = false;
      if (bc && guess.allFinite()) {
        Eigen::Vector2d xu = guess;
        for (int it = 0; it < 8 && !done; ++it) {
          Eigen::Matrix2d jac;
          const Eigen::Vector2d r = coeffs.Distort(xu, &jac) - target;
          if (r.norm() * camera.fx() < 1e-10) {
            done = true;
            break;
          }
          if (!(jac.determinant() > 0)) break;
          xu -= jac.inverse() * r;
        }
        if (done) {
          valid[k] = ray_point(Eigen::Vector3d(xu.x(), xu.y(), 1.0).normalized(), &corner[k]);
          guess = xu;
        }
      }
      if (!done) {
        const auto ray = camera.Unproject({x - 0.5, y - 0.5});
        valid[k] = ray && ray_point(*ray, &corner[k]);
        guess = ray && ray->z() > 0 ? Eigen::Vector2d(ray->x() / ray->z(), ray->y() / ray->z())
                                    : Eigen::Vector2d(NAN, NAN);
      }
    }
  }
  const double s = board.square_m, m = board.margin_squares;
  const double x_min = -(1 + m) * s, x_max = (board.cols + m) * s, y_min = -(1 + m) * s, y_max = (board.rows + m) * s;
  auto value = [&](const Eigen::Vector2d& p) {
    const int c = board.ColourAt(p.x(), p.y());
    return c < 0 ? options.background : c == 0 ? options.black : options.white;
  };
  auto cell = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector2d(std::floor(p.x() / s), std::floor(p.y() / s));
  };
  Image<float> img(w, h, 1);
  const int ns = options.supersampling;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t k00 = size_t(y) * size_t(w + 1) + size_t(x), k10 = k00 + 1, k01 = k00 + size_t(w + 1),
                   k11 = k01 + 1;
      const bool all_valid = valid[k00] && valid[k10] && valid[k01] && valid[k11];
      const Eigen::Vector2d c[4] = {corner[k00], corner[k10], corner[k01], corner[k11]};
      if (all_valid) {
        bool uniform = true;
        const bool inside0 = c[0].x() >= x_min && c[0].x() < x_max && c[0].y() >= y_min && c[0].y() < y_max;
        if (inside0) {
          const Eigen::Vector2d c0 = cell(c[0]);
          for (int q = 1; q < 4; ++q) uniform = uniform && cell(c[q]) == c0;
        } else {
          // Off the board: uniform when all four corners lie beyond the same
          // side of the board's rectangle (the pixel is convex).
          bool left = true, right = true, above = true, below = true;
          for (const auto& p : c) {
            left = left && p.x() < x_min;
            right = right && p.x() >= x_max;
            above = above && p.y() < y_min;
            below = below && p.y() >= y_max;
          }
          uniform = left || right || above || below;
        }
        if (uniform) {
          img.At(x, y) = float(value(c[0]));
          continue;
        }
      }
      Rng rng = Rng::For(options.seed, 0, uint64_t(y) * uint64_t(w) + uint64_t(x), 0, kJitterPurpose);
      double sum = 0;
      for (int b = 0; b < ns; ++b) {
        for (int a = 0; a < ns; ++a) {
          const double fa = (a + rng.NextDouble()) / ns, fb = (b + rng.NextDouble()) / ns;
          Eigen::Vector2d p;
          bool hit = true;
          if (all_valid) {
            p = (1 - fa) * (1 - fb) * c[0] + fa * (1 - fb) * c[1] + (1 - fa) * fb * c[2] + fa * fb * c[3];
          } else {
            const auto ray = camera.Unproject({x - 0.5 + fa, y - 0.5 + fb});
            hit = ray && ray_point(*ray, &p);
          }
          sum += hit ? value(p) : options.background;
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

#include "scene/trailing_wheel.h"

#include <algorithm>
#include <cmath>

namespace lt {

Eigen::Vector2d WheelHalfAngle(double psi_rad) { return {std::sin(0.5 * psi_rad), std::cos(0.5 * psi_rad)}; }

double WheelAngle(const Eigen::Vector2d& half) { return 2 * std::atan2(half.x(), half.y()); }

Eigen::Vector2d TrailAlong(const Eigen::Vector2d& half, double s_m, double trail_m, double kappa_per_m) {
  // With u = tan(psi / 2) = x / y: du/ds = -u / w - kappa (1 + u^2) / 2, which is the
  // linear flow (x, y)' = M (x, y) of M = [[-a/2, -kappa/2], [kappa/2, a/2]], a = 1/w.
  // M is traceless with M^2 = lambda^2 I, lambda^2 = (a^2 - kappa^2) / 4, so
  // exp(s M) = c I + S M with (c, S) = (cosh, sinh / lambda), (cos, sin / mu) for
  // lambda^2 = -mu^2 < 0, or (1, s) for lambda = 0. Only the direction of (x, y)
  // matters, so for lambda > 0 both are divided by cosh; steps of lambda s <= 8 keep
  // the contracted component to a relative error of about 1e-10 (1 - tanh cancels).
  const double a = 1 / trail_m;
  const double l2 = 0.25 * (a * a - kappa_per_m * kappa_per_m);
  const double l = std::sqrt(std::abs(l2));
  const double max_step = l2 > 0 ? 8 / l : s_m;
  Eigen::Vector2d out = half;
  for (double left = s_m; left > 0;) {
    const double s = std::min(left, max_step);
    left -= s;
    double c = 1, S = s;
    if (l2 > 0) {
      S = std::tanh(l * s) / l;
    } else if (l2 < 0) {
      c = std::cos(l * s);
      S = std::sin(l * s) / l;
    }
    const Eigen::Vector2d m_out(-0.5 * a * out.x() - 0.5 * kappa_per_m * out.y(),
                                0.5 * kappa_per_m * out.x() + 0.5 * a * out.y());
    const Eigen::Vector2d next = c * out + S * m_out;
    const double n = next.norm();
    if (!(n > 1e-300)) break;  // held at the repelling angle: it stays there
    out = next / n;
  }
  return out;
}

}  // namespace lt

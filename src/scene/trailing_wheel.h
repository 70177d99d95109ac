// A wheel trailing its pivot at a fixed distance (a caster wheel, a towed trailer):
// the heading it takes as the pivot follows a path.
//
// Along bed-plane path length s, with phi(s) the path's tangent angle and theta the
// wheel's heading, the wheel (at distance w behind the pivot, pulled along its own
// axis) turns at
//
//     d theta / ds = -sin(psi) / w,   psi = theta - phi  (the wheel's angle off the path),
//
// so the heading never turns faster than v / w at path speed v, whatever the path
// does: corners, reversals, tight arcs. On a move of constant curvature kappa (0 on a
// line, sweep / length on an arc), d psi / ds = -sin(psi) / w - kappa: a Riccati
// equation in tan(psi / 2) whose flow is linear in the half-angle vector
// (sin(psi / 2), cos(psi / 2)), so it is solved in closed form (a 2x2 matrix
// exponential), with no step size and no growing error over long paths.
#pragma once

#include <Eigen/Core>

namespace lt {

// The half-angle vector of psi, unit length: psi = 2 atan2(x, y).
Eigen::Vector2d WheelHalfAngle(double psi_rad);
double WheelAngle(const Eigen::Vector2d& half);

// The half-angle vector after path length s_m (>= 0) along a move of curvature
// kappa_per_m (counter-clockwise positive) for a wheel at trail_m behind the pivot;
// unit length.
Eigen::Vector2d TrailAlong(const Eigen::Vector2d& half, double s_m, double trail_m, double kappa_per_m);

}  // namespace lt

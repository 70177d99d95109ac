// The sheet's window over a frame's chief hits (SheetWindowOfHits) and the
// test of a query's reach against it (LaserEntryTree::Covers).
#include <algorithm>
#include <cmath>

#include "render/laser_entry_tree.h"

namespace lt {

namespace {

// The window takes each hit's angular reach with this margin, so that points a
// little nearer the projector than the hits are still covered.
constexpr double kWindowMargin = 1.05;

double AngularReach(double reach, double r) { return std::asin(std::min(1.0, reach / r)); }

}  // namespace

SheetWindow SheetWindowOfHits(const PointEmitter& e, int sheet, std::span<const ChiefHit> hits,
                              std::span<const double> reach_m, double extra_m) {
  SheetWindow w;
  if (!e.laser) return w;
  const LaserProjector& laser = *e.laser;
  double lo = INFINITY, hi = -INFINITY;
  for (const ChiefHit& h : hits) {
    if (!h.valid || h.material >= reach_m.size()) continue;
    if (!(reach_m[h.material] > 0)) continue;
    const double reach = reach_m[h.material] + extra_m;
    const Eigen::Vector3d p = e.projector_from_world * h.p_world;
    const double r = p.norm();
    if (!(r > 0)) continue;
    const LaserProjector::SheetAngles a = laser.Angles(sheet, p / r);
    const double margin = kWindowMargin * AngularReach(reach, r);
    if (std::abs(a.psi) > LaserProjector::kDefaultCutoffSigma * laser.SheetSigma(r) + margin) continue;
    lo = std::min(lo, a.phi - margin);
    hi = std::max(hi, a.phi + margin);
    w.r_far = std::max(w.r_far, r + reach);
  }
  const double limit = laser.FanHalfWidth();
  if (lo <= -limit) lo = -limit, w.closed_lo = true;
  if (hi >= limit) hi = limit, w.closed_hi = true;
  if (hi > lo) w.phi_lo = lo, w.phi_hi = hi;
  return w;
}

bool LaserEntryTree::Covers(const Eigen::Vector3d& p, double r_max) const {
  const Eigen::Vector3d q = projector_from_world_ * (p - origin_);
  const double r = q.norm();
  if (!(r > 0)) return false;
  const double phi = laser_->Phi(sheet_, q / r);
  const double m = AngularReach(r_max, r);
  return (window_.closed_lo || phi - m >= window_.phi_lo) && (window_.closed_hi || phi + m <= window_.phi_hi);
}

}  // namespace lt

// The laser light entering subsurface materials, cached for one frame: a
// quadrature of one laser sheet's lit surface and a tree over it that sums the
// diffusion profile's light at any exit point without noise.
//
// Subsurface light leaving x_o is (path_tracer_subsurface.cpp)
//   L_o = C_o * integral over the lit surface of R(|x_i - x_o|) (1 - E(cos_i)) E_i(x_i) dA_i.
// E_i dA_i is the power the sheet sends through the solid angle that lands on
// dA_i, I(w) dw, so over a grid of directions w_j = (phi_j, psi_j) of the sheet
// (dw = cos psi dpsi dphi), each cast once from the projector to its first
// hit x_j,
//   integral ~= sum_j R(|x_j - x_o|) W_j,   W_j = I(w_j) cos psi_j dpsi dphi (1 - E(cos_i,j)).
// The grid: phi over the sheet's window (every fan angle within a profile's
// reach of a surface the camera sees) at a step that puts entry points
// `spacing` apart on the farthest such surface; psi over +-kAcrossSigmas of the
// sheet's Gaussian at a step of at most sigma / 2 and the same spacing (the
// trapezoid rule on a Gaussian). Each x_j stands for the patch
// dA_j = r^2 dw / cos_i around it. Along psi, neighbouring entry points on one
// surface (same material, normals within ~25 degrees, no gap) merge into
// segments kSegmentSigmas sigma wide: a segment keeps its weight, weighted
// centroid c and second moment M about c (3x3; each patch counted as a disc
// of its area), m2 = trace M.
// A segment or node small seen from x_o (m2 < kOpeningRatio^2 r^2) stands for
// its entry points by the Taylor expansion of R about c to second order: with
// d = c - x_o, r = |d|, u = d / r,
//   mean of R ~= R(r) + 1/2 tr(H M),  H = R'' u u^T + (R' / r)(I - u u^T),
// R being Burley's two exponentials over r, whose derivatives are closed form
// (a nearer leaf: R(r) at its centroid). Without the second-order term the
// centroid alone reads R low (R is convex): 1.1% of the flat slab's light in
// SubsurfaceStripe. Within s = sqrt(kSmoothing m2) of c the profile's light
// inside s is spread evenly over the disc, A CDF(s) / (pi s^2), so no light
// is lost to the 1/r peak.
//
// The tree (segments in grid order, split in halves) stores per node the
// summed weight, the weighted centroid and second moment, a radius about the centroid bounding its entry points,
// the material (or mixed) and the bounding box of the normals, which bounds
// n . n_o over them (a cone about the mean normal was looser: where the stripe
// crosses a step, top and wall normals 90 degrees apart, its bound put the wall
// beyond 90 degrees of a top point's normal and every node holding both was
// opened down to its leaves). A query skips a node beyond the profile's reach,
// of another material, or whose normals all face away from n_o; it opens one
// unless it is small seen from x_o (m2 < kOpeningRatio^2 |c - x_o|^2), of one
// material, and all its normals face n_o, in which case it stands for its
// entry points as above.
// Entry points count as in the Monte Carlo estimator: the same material as x_o,
// within the profile's radius r_max, and lit on the side that x_o's normal faces.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "render/frame_lights.h"
#include "render/stripe_truth.h"
#include "render/subsurface_profile.h"
#include "scene/embree_scene.h"

namespace lt {

// The range of fan angles phi of one sheet that a frame needs, and whether the
// sheet has no light beyond each end (the fan's edge): then any point past that
// end is covered.
struct SheetWindow {
  double phi_lo = 0, phi_hi = 0;
  bool closed_lo = false, closed_hi = false;
  double r_far = 0;  // largest distance from the projector of a surface within the window
  bool empty() const { return !(phi_hi > phi_lo); }
};

// The window of sheet `sheet` of emitter e (a laser) over the camera's chief
// hits: every hit on a subsurface material (reach_m[material] > 0) that the
// sheet passes within that reach, widened by the reach. `extra_m` widens each
// hit's reach further: a cache for another pose of the scanner than the chief
// rays' must cover the points its camera sees, up to that far from the hits.
SheetWindow SheetWindowOfHits(const PointEmitter& e, int sheet, std::span<const ChiefHit> hits,
                              std::span<const double> reach_m, double extra_m = 0);

class LaserEntryTree {
 public:
  // A symmetric 3x3 second moment: xx yy zz xy xz yz.
  using Moment = std::array<float, 6>;
  static constexpr double kAcrossSigmas = 4.5;
  static constexpr double kOpeningRatio = 0.25;
  // An inner node stands for its points only within kRadiusRatio times its
  // distance of their bounding sphere's centre (its radius).
  static constexpr double kRadiusRatio = 0.75;
  static constexpr double kSegmentSigmas = 1.0;
  static constexpr float kSmoothing = 1.0f;
  static constexpr size_t kMaxPoints = size_t(1) << 22;

  // Casts the grid of sheet `sheet` of e (a laser) over `window`; keeps the hits
  // on subsurface materials. `spacing_m`: entry-point spacing along the sheet.
  // Returns null when the grid would exceed kMaxPoints (the caller falls back
  // to Monte Carlo). `rays` counts the rays cast.
  static std::unique_ptr<LaserEntryTree> Build(const EmbreeScene& scene, const PointEmitter& e, int sheet,
                                               const SheetWindow& window, double spacing_m, uint64_t* rays);

  // True when every entry point within r_max of p (world) lies in the window.
  bool Covers(const Eigen::Vector3d& p, double r_max) const;
  // sum_j R(r_eff,j) W_j over the entry points on `material` within r_max of x
  // (world) whose normal, oriented toward the projector, has n_o . n >= 0.
  // `opening_ratio` 0 opens every node down to the segments (the sum the
  // expansion approximates). `evaluated`, when given, is incremented by the
  // number of nodes and segments evaluated (the query's cost).
  double Sum(const Eigen::Vector3d& x, const Eigen::Vector3d& n_o, uint32_t material, const BurleyProfile& profile,
             double r_max, double opening_ratio = kOpeningRatio, int64_t* evaluated = nullptr) const;
  // The same sum over every segment in order, without the tree: equal to Sum
  // with opening_ratio 0 bit for bit, since the tree only skips nodes none of
  // whose segments count (a reference for tests). `leaf_opening_ratio`: each
  // segment evaluated as Sum evaluates a segment at that ratio (with the second
  // order term where it is small seen from x), so that with kOpeningRatio the
  // difference from Sum is the error of the nodes standing for their segments.
  double SumOverSegments(const Eigen::Vector3d& x, const Eigen::Vector3d& n_o, uint32_t material,
                         const BurleyProfile& profile, double r_max, double leaf_opening_ratio = 0.0) const;

  size_t points() const { return points_; }

 private:
  // The traversal's fields, one cache line a node; the second moments, read
  // only where a node is evaluated, lie in moments_ (same index).
  struct alignas(64) Node {
    Eigen::Vector3f c;           // weighted centroid, relative to origin_
    Eigen::Vector3f n_lo, n_hi;  // bounding box of the unit normals
    float w = 0;                 // summed weight W
    float m2 = 0;                // weighted mean squared distance from c (m^2): trace of the moment
    float radius = 0;            // bounds |p - c| over the node's entry points (with a margin)
    int32_t material = -1;       // -1: mixed
    uint32_t right = 0;          // right child (left child: this + 1); 0 for a leaf
  };
  struct Point {
    Eigen::Vector3f p, n;
    float w;
    Moment m;  // second moment about p
    uint32_t material;
  };
  struct Segment;
  struct Kernel;
  static void CosBounds(const Node& node, const Eigen::Vector3f& n_o, float* cos_lo, float* cos_hi);
  // query_normals: DistinctNormals of all the points, for the normal splits.
  uint32_t BuildNode(std::vector<Point>& pts, size_t begin, size_t end, std::span<const Eigen::Vector3f> query_normals);
  static std::vector<Eigen::Vector3f> DistinctNormals(const std::vector<Point>& pts);
  // The box of pts' normals (n_lo, n_hi; the rest default).
  static Node NormalBox(std::span<const Point> pts);
  // Whether a node's box of normals has n . n_o both ways for some n_o of query_normals.
  static bool Straddles(const Node& box, std::span<const Eigen::Vector3f> query_normals);

  Eigen::Vector3d origin_;  // of the float coordinates (the projector)
  Eigen::Matrix3d projector_from_world_;
  const LaserProjector* laser_ = nullptr;
  int sheet_ = 0;
  SheetWindow window_;
  std::vector<Node> nodes_;
  std::vector<Moment> moments_;  // weighted second moment about c (m^2), per node
  size_t points_ = 0;
};

}  // namespace lt

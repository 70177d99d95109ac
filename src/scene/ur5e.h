// Kinematics of the Universal Robots UR5e arm: forward kinematics, the analytic
// inverse (up to 8 solutions), and joint paths along a sequence of flange poses that
// stay continuous and respect the joint limits, or report where they cannot.
//
// Geometry: the manufacturer's standard Denavit-Hartenberg parameters,
//   d1 = 0.1625, a2 = -0.425, a3 = -0.3922, d4 = 0.1333, d5 = 0.0997, d6 = 0.0996 (m),
//   alpha = [pi/2, 0, 0, pi/2, -pi/2, 0],
// link transform A_i = Rz(q_i) Tz(d_i) Tx(a_i) Rx(alpha_i), base_from_flange =
// A_1 ... A_6. The base frame is UR's base frame (z up along joint 1; note that
// PolyScope's "base" view is rotated 180 degrees about z from it); the flange frame
// is UR's tool0 frame with zero TCP (z out of the flange face).
//
// Limits (Universal Robots e-Series user manual, UR5e): every joint turns +-360
// degrees (+-2 pi) and at most 180 deg/s (pi rad/s), base, shoulder, elbow and the
// three wrists alike. The elbow's rated range is +-360 degrees but the shoulder gets
// in its way beyond about +-180 degrees; Ur5eLimits can be narrowed for that.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"

namespace lt {

using JointVector = Eigen::Matrix<double, 6, 1>;  // radians, base to wrist 3

struct Ur5eLimits {
  JointVector position_min_rad = JointVector::Constant(-2 * M_PI);
  JointVector position_max_rad = JointVector::Constant(2 * M_PI);
  JointVector speed_max_rad_s = JointVector::Constant(M_PI);
  // Throws std::invalid_argument unless min < max and speeds > 0, all finite.
  void Check() const;
};

// The pose of the flange in the base frame.
Pose Ur5eForward(const JointVector& q);
// The frames of the base and the six links after each joint (index 0 = base, 6 =
// flange), for drawing the arm.
std::array<Pose, 7> Ur5eLinkFrames(const JointVector& q);

// All joint vectors (each joint in (-pi, pi]) that put the flange at the pose; empty
// when the pose is out of reach. Up to 8 (2 shoulder x 2 wrist x 2 elbow branches).
// At the wrist singularity (joint 5 at 0 or pi, joints 4 and 6 on one axis) joint 6
// is not determined: it takes `q6_hint` and joint 4 makes up the rest.
std::vector<JointVector> Ur5eInverse(const Pose& base_from_flange, double q6_hint = 0);

// The inverse solution nearest to `previous` (Euclidean in joint space), with each
// joint moved by whole turns to lie nearest its previous value inside the limits.
// nullopt when out of reach; `limits_violated` (when not null) is set when a
// solution exists but none fits the position limits.
std::optional<JointVector> Ur5eNearestSolution(const Pose& base_from_flange, const JointVector& previous,
                                               const Ur5eLimits& limits, bool* limits_violated = nullptr);

// One problem on a joint path.
struct JointPathProblem {
  enum class Kind { kUnreachable, kPositionLimit, kSpeedLimit };
  Kind kind = Kind::kUnreachable;
  size_t waypoint = 0;  // index of the waypoint where it happens (for speed: the later one)
  int joint = -1;       // 0..5, -1 for unreachable
  double value = 0;     // kPositionLimit: the joint angle (rad); kSpeedLimit: the speed needed (rad/s, inf for no time)
  double limit = 0;     // the limit it breaks
  double delta_rad = 0; // kSpeedLimit: the joint's change between the two waypoints
  // kSpeedLimit where the step changes the arm's configuration because the nearest
  // solution would put a joint past its position limit (a joint wound up by a path
  // that turns the tool one way): that joint, its angle there and the limit; -1 when not.
  int wound_joint = -1;
  double wound_value = 0;
  double wound_limit = 0;
  // "wrist 3 needs 312 deg/s, limit 180 deg/s", and for a wound joint "; the arm
  // changes configuration: wrist 3 would reach -362 deg, past its limit -360 deg"
  std::string Describe() const;
};

// Joint names: "base", "shoulder", "elbow", "wrist 1", "wrist 2", "wrist 3".
const char* Ur5eJointName(int joint);

struct RobotWaypoint {
  double t_s = 0;
  Pose base_from_flange = Pose::Identity();
};

struct JointPath {
  std::vector<double> t_s;
  std::vector<JointVector> q;  // one per waypoint solved (all of them unless `failure`)
  // The first waypoint that is out of reach or outside the position limits; the
  // path stops there.
  std::optional<JointPathProblem> failure;
  // Speed limits: how many steps between waypoints break one, the first and the worst
  // (largest ratio of speed to limit).
  size_t speed_violations = 0;
  std::optional<JointPathProblem> first_speed_violation;
  std::optional<JointPathProblem> worst_speed_violation;
  JointVector max_speed_rad_s = JointVector::Zero();  // largest speed each joint needs
};

// Solves the waypoints in order, each nearest to the previous solution (the first
// nearest to `start`), so the arm moves continuously; speeds are joint changes over
// the time between consecutive waypoints (times must not decrease).
JointPath SolveJointPath(const std::vector<RobotWaypoint>& waypoints, const JointVector& start,
                         const Ur5eLimits& limits);

}  // namespace lt

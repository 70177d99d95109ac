// UR5e kinematics: forward kinematics against the arm's zero pose, the analytic
// inverse against forward kinematics over many random joint vectors, the wrist
// singularity, continuity along a smooth path (with the wrist winding past +-180
// degrees), and every kind of problem reported at its waypoint.
#include "scene/ur5e.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"

namespace lt {
namespace {

using ::testing::HasSubstr;

double PoseError(const Pose& a, const Pose& b) { return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff(); }

// Joint distance modulo whole turns.
double WrappedDistance(const JointVector& a, const JointVector& b) {
  double d = 0;
  for (int j = 0; j < 6; ++j) d = std::max(d, std::abs(std::remainder(a[j] - b[j], 2 * M_PI)));
  return d;
}

TEST(Ur5e, ZeroPoseIsTheStretchedArm) {
  // All joints at 0: the arm lies along -x (a2 + a3), the wrist offsets d4 and d6
  // point along -y, d5 down; the flange faces -y.
  Pose p = Ur5eForward(JointVector::Zero());
  EXPECT_TRUE(p.translation().isApprox(Eigen::Vector3d(-0.425 - 0.3922, -0.1333 - 0.0996, 0.1625 - 0.0997), 1e-15));
  EXPECT_TRUE((p.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(0, -1, 0), 1e-15));
  // Joint 1 turns the whole arm about the base z axis.
  JointVector q = JointVector::Zero();
  q[0] = M_PI / 2;
  Pose turned = Ur5eForward(q);
  EXPECT_TRUE(turned.translation().isApprox(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) * p.translation(), 1e-15));
  auto frames = Ur5eLinkFrames(q);
  EXPECT_LT(PoseError(frames[6], turned), 1e-15);
  EXPECT_NEAR(frames[1].translation().z(), 0.1625, 1e-15);
}

TEST(Ur5e, InverseOfForwardOverRandomJointVectors) {
  // 2000 random joint vectors in (-pi, pi]^6: every solution reproduces the pose to
  // 1e-9 and one of them is the joint vector we started from.
  int checked = 0, eight = 0;
  for (int k = 0; k < 2000; ++k) {
    Rng rng = Rng::For(7, k, 0, 0, 0);
    JointVector q;
    for (int j = 0; j < 6; ++j) q[j] = (2 * rng.NextDouble() - 1) * M_PI;
    Pose pose = Ur5eForward(q);
    std::vector<JointVector> solutions = Ur5eInverse(pose, q[5]);
    ASSERT_FALSE(solutions.empty()) << k;
    ASSERT_LE(solutions.size(), 8u);
    double nearest = 1e9;
    for (const JointVector& s : solutions) {
      EXPECT_LT(PoseError(Ur5eForward(s), pose), 1e-9) << k;
      for (int j = 0; j < 6; ++j) EXPECT_TRUE(s[j] > -M_PI && s[j] <= M_PI);
      nearest = std::min(nearest, WrappedDistance(s, q));
    }
    // Near a singularity (wrist: sin q5 ~ 0; elbow stretched: sin q3 ~ 0) the
    // solutions bunch up and recover q less precisely; the pose itself still holds.
    bool well_conditioned = std::abs(std::sin(q[4])) > 1e-2 && std::abs(std::sin(q[2])) > 1e-2;
    if (well_conditioned) {
      EXPECT_LT(nearest, 1e-7) << k;
      ++checked;
    }
    eight += solutions.size() == 8;
  }
  EXPECT_GT(checked, 1900);
  EXPECT_GT(eight, 1000);  // generic poses have all 8 branches
}

TEST(Ur5e, WristSingularityTakesTheHint) {
  JointVector q;
  q << 0.3, -1.2, 1.4, -0.5, 0.0, 0.7;  // q5 = 0: joints 4 and 6 on one axis
  Pose pose = Ur5eForward(q);
  for (double hint : {0.0, 0.7, -2.0}) {
    std::vector<JointVector> solutions = Ur5eInverse(pose, hint);
    ASSERT_FALSE(solutions.empty());
    bool any_hint = false;
    for (const JointVector& s : solutions) {
      EXPECT_LT(PoseError(Ur5eForward(s), pose), 1e-9) << hint;
      if (std::abs(s[4]) < 1e-6) {
        EXPECT_NEAR(s[5], hint, 1e-12);
        any_hint = true;
      }
    }
    EXPECT_TRUE(any_hint);
  }
}

// A nozzle-like flange pose: pointing down (flange z = -z), turned by `heading` about
// the vertical, at position p.
Pose DownPose(const Eigen::Vector3d& p, double heading) {
  Pose pose = Pose::Identity();
  pose.linear() = (Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  pose.translation() = p;
  return pose;
}

// A circle of radius 0.15 m in front of the robot, 1 mm steps at 20 mm/s, the flange
// turning with the tangent through `laps` turns.
std::vector<RobotWaypoint> CircleWaypoints(double laps) {
  std::vector<RobotWaypoint> waypoints;
  const double radius = 0.15, step = 0.001, v = 0.02;
  const int n = int(2 * M_PI * laps * radius / step);
  for (int k = 0; k <= n; ++k) {
    double a = k * step / radius;
    RobotWaypoint w;
    w.t_s = k * step / v;
    w.base_from_flange = DownPose(Eigen::Vector3d(0.45 + radius * std::cos(a), radius * std::sin(a), 0.15), a + M_PI / 2);
    waypoints.push_back(w);
  }
  return waypoints;
}

JointVector Home() {
  JointVector start;
  start << 0, -M_PI / 2, M_PI / 2, -M_PI / 2, -M_PI / 2, 0;
  return start;
}

TEST(Ur5e, JointPathIsContinuousAlongASmoothPath) {
  // Most of a lap: wrist 3 turns through nearly 360 degrees, across +-180 without a
  // jump (joint values are unwrapped, not folded into (-pi, pi]).
  std::vector<RobotWaypoint> waypoints = CircleWaypoints(0.9);
  JointPath path = SolveJointPath(waypoints, Home(), Ur5eLimits{});
  ASSERT_FALSE(path.failure) << path.failure->Describe();
  ASSERT_EQ(path.q.size(), waypoints.size());
  double max_step = 0;
  for (size_t k = 0; k < path.q.size(); ++k) {
    EXPECT_LT(PoseError(Ur5eForward(path.q[k]), waypoints[k].base_from_flange), 1e-9) << k;
    if (k > 0) max_step = std::max(max_step, (path.q[k] - path.q[k - 1]).cwiseAbs().maxCoeff());
  }
  // 1 mm on a 150 mm radius turns the flange by 1/150 rad; no joint moves more than a
  // few times that in one step.
  EXPECT_LT(max_step, 0.05);
  EXPECT_GT(std::abs(path.q.back()[5] - path.q.front()[5]), 0.9 * 2 * M_PI - 0.1);
  double widest = 0;
  for (const auto& q : path.q) widest = std::max(widest, std::abs(q[5]));
  EXPECT_GT(widest, M_PI);  // crossed the +-180 degree fold
  EXPECT_EQ(path.speed_violations, 0u);
  EXPECT_GT(path.max_speed_rad_s.maxCoeff(), 0.0);
}

TEST(Ur5e, WindingPastTheJointRangeIsReportedNotClipped) {
  // Two laps need wrist 3 beyond -360 degrees. The nearest solution inside the limits
  // flips the wrist: a jump no joint can make at 20 mm/s, reported where it happens.
  std::vector<RobotWaypoint> waypoints = CircleWaypoints(2.0);
  JointPath path = SolveJointPath(waypoints, Home(), Ur5eLimits{});
  ASSERT_FALSE(path.failure);
  ASSERT_GE(path.speed_violations, 1u);
  size_t k = path.first_speed_violation->waypoint;
  EXPECT_GT(std::abs(path.q[k - 1][5]), 2 * M_PI - 2.0 / 150);  // wrist 3 was at its limit
  // The report says why: the nearest solution would take wrist 3 past its limit.
  const JointPathProblem& flip = *path.first_speed_violation;
  EXPECT_EQ(flip.wound_joint, 5);
  EXPECT_GT(std::abs(flip.wound_value), 2 * M_PI);
  EXPECT_EQ(std::abs(flip.wound_limit), 2 * M_PI);
  EXPECT_THAT(flip.Describe(), HasSubstr("; the arm changes configuration: wrist 3 would reach"));
  EXPECT_THAT(flip.Describe(), HasSubstr("deg, past its limit " + std::string(flip.wound_limit < 0 ? "-" : "") + "360 deg"));
  for (size_t i = 1; i < k; ++i) EXPECT_LT((path.q[i] - path.q[i - 1]).cwiseAbs().maxCoeff(), 0.05) << i;
  for (const auto& q : path.q) EXPECT_LE(q.cwiseAbs().maxCoeff(), 2 * M_PI);
}

TEST(Ur5e, ProblemsAreReportedAtTheirWaypoint) {
  const JointVector start = Home();
  // Out of reach: 2 m from the base.
  std::vector<RobotWaypoint> w(3);
  w[0].base_from_flange = DownPose(Eigen::Vector3d(0.4, 0.1, 0.2), 0);
  w[1].t_s = 1;
  w[1].base_from_flange = DownPose(Eigen::Vector3d(0.4, 0.12, 0.2), 0);
  w[2].t_s = 2;
  w[2].base_from_flange = DownPose(Eigen::Vector3d(2.0, 0, 0.2), 0);
  EXPECT_TRUE(Ur5eInverse(w[2].base_from_flange).empty());
  JointPath unreachable = SolveJointPath(w, start, Ur5eLimits{});
  ASSERT_TRUE(unreachable.failure);
  EXPECT_EQ(unreachable.failure->kind, JointPathProblem::Kind::kUnreachable);
  EXPECT_EQ(unreachable.failure->waypoint, 2u);
  EXPECT_EQ(unreachable.q.size(), 2u);
  EXPECT_THAT(unreachable.failure->Describe(), HasSubstr("out of the UR5e's reach"));

  // Position limits: the base confined to +-0.1 rad cannot reach a point at 90 degrees.
  Ur5eLimits narrow;
  narrow.position_min_rad[0] = -0.1;
  narrow.position_max_rad[0] = 0.1;
  // The first two waypoints sit where the base is at 0: y = -d4 puts the wrist centre
  // d4 off the arm's plane at q1 = 0.
  w[0].base_from_flange = DownPose(Eigen::Vector3d(0.4, -0.1333, 0.2), 0);
  w[1].base_from_flange = DownPose(Eigen::Vector3d(0.42, -0.1333, 0.2), 0);
  w[2].base_from_flange = DownPose(Eigen::Vector3d(0, 0.4, 0.2), 0);
  JointPath limited = SolveJointPath(w, start, narrow);
  ASSERT_TRUE(limited.failure);
  EXPECT_EQ(limited.failure->kind, JointPathProblem::Kind::kPositionLimit);
  EXPECT_EQ(limited.failure->waypoint, 2u);
  EXPECT_EQ(limited.failure->joint, 0);
  EXPECT_THAT(limited.failure->Describe(), HasSubstr("base at"));

  // Speed: 90 degrees about the vertical in 0.1 s needs wrist 3 at 900 deg/s; a turn
  // with no time between waypoints needs infinite speed. Reported, never clipped.
  std::vector<RobotWaypoint> fast(3);
  fast[0].base_from_flange = DownPose(Eigen::Vector3d(0.4, 0.1, 0.2), 0);
  fast[1].t_s = 0.1;
  fast[1].base_from_flange = DownPose(Eigen::Vector3d(0.4, 0.1, 0.2), M_PI / 2);
  fast[2].t_s = 0.1;
  fast[2].base_from_flange = DownPose(Eigen::Vector3d(0.4, 0.1, 0.2), M_PI / 4);
  JointPath too_fast = SolveJointPath(fast, start, Ur5eLimits{});
  ASSERT_FALSE(too_fast.failure);
  EXPECT_EQ(too_fast.speed_violations, 2u);
  ASSERT_TRUE(too_fast.first_speed_violation);
  EXPECT_EQ(too_fast.first_speed_violation->waypoint, 1u);
  EXPECT_EQ(too_fast.first_speed_violation->joint, 5);
  EXPECT_NEAR(too_fast.first_speed_violation->value, (M_PI / 2) / 0.1, 1e-9);
  EXPECT_EQ(too_fast.first_speed_violation->Describe(), "wrist 3 needs 900 deg/s, limit 180 deg/s");
  EXPECT_EQ(too_fast.first_speed_violation->wound_joint, -1);  // a fast turn, no limit involved
  ASSERT_TRUE(too_fast.worst_speed_violation);
  EXPECT_EQ(too_fast.worst_speed_violation->waypoint, 2u);
  EXPECT_THAT(too_fast.worst_speed_violation->Describe(), HasSubstr("wrist 3 turns 45 deg in no time"));
}

TEST(Ur5e, LimitsAreChecked) {
  Ur5eLimits l;
  EXPECT_NO_THROW(l.Check());
  l.speed_max_rad_s[2] = 0;
  EXPECT_THROW(l.Check(), std::invalid_argument);
  l = Ur5eLimits{};
  l.position_min_rad[1] = 1;
  l.position_max_rad[1] = 1;
  EXPECT_THROW(l.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace lt

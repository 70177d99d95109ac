#include "scene/ur5e.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>

namespace lt {

namespace {

constexpr double kD1 = 0.1625;
constexpr double kA2 = -0.425;
constexpr double kA3 = -0.3922;
constexpr double kD4 = 0.1333;
constexpr double kD5 = 0.0997;
constexpr double kD6 = 0.0996;
constexpr double kD[6] = {kD1, 0, 0, kD4, kD5, kD6};
constexpr double kA[6] = {0, kA2, kA3, 0, 0, 0};
constexpr double kAlpha[6] = {M_PI / 2, 0, 0, M_PI / 2, -M_PI / 2, 0};
// Cosines beyond +-1 by this much are rounding (clamped); further is out of reach.
constexpr double kCosSlack = 1e-10;
// |sin q5| below this is the wrist singularity.
constexpr double kWristSingular = 1e-10;
constexpr double kRadToDeg = 180.0 / M_PI;

// A_i = Rz(q) Tz(d) Tx(a) Rx(alpha).
Pose LinkTransform(int i, double q) {
  const double cq = std::cos(q), sq = std::sin(q);
  const double ca = std::cos(kAlpha[i]), sa = std::sin(kAlpha[i]);
  Pose a = Pose::Identity();
  a.linear() << cq, -sq * ca, sq * sa,  //
      sq, cq * ca, -cq * sa,            //
      0, sa, ca;
  a.translation() << kA[i] * cq, kA[i] * sq, kD[i];
  return a;
}

// Angle in (-pi, pi].
double Wrap(double a) {
  a = std::remainder(a, 2 * M_PI);
  if (a <= -M_PI) a += 2 * M_PI;
  return a;
}

// acos with rounding slack; nullopt beyond it.
std::optional<double> SafeAcos(double c) {
  if (c > 1 + kCosSlack || c < -1 - kCosSlack || !std::isfinite(c)) return std::nullopt;
  return std::acos(std::clamp(c, -1.0, 1.0));
}

std::string Deg(double rad) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", rad * kRadToDeg);
  return buf;
}

}  // namespace

void Ur5eLimits::Check() const {
  for (int j = 0; j < 6; ++j) {
    if (!std::isfinite(position_min_rad[j]) || !std::isfinite(position_max_rad[j]) ||
        !(position_min_rad[j] < position_max_rad[j])) {
      throw std::invalid_argument(std::string("joint limits of ") + Ur5eJointName(j) + ": need finite min < max");
    }
    if (!(std::isfinite(speed_max_rad_s[j]) && speed_max_rad_s[j] > 0)) {
      throw std::invalid_argument(std::string("speed limit of ") + Ur5eJointName(j) + " must be > 0");
    }
  }
}

const char* Ur5eJointName(int joint) {
  static const char* names[6] = {"base", "shoulder", "elbow", "wrist 1", "wrist 2", "wrist 3"};
  return joint >= 0 && joint < 6 ? names[joint] : "none";
}

Pose Ur5eForward(const JointVector& q) {
  Pose t = Pose::Identity();
  for (int i = 0; i < 6; ++i) t = t * LinkTransform(i, q[i]);
  return t;
}

std::array<Pose, 7> Ur5eLinkFrames(const JointVector& q) {
  std::array<Pose, 7> frames;
  frames[0] = Pose::Identity();
  for (int i = 0; i < 6; ++i) frames[i + 1] = frames[i] * LinkTransform(i, q[i]);
  return frames;
}

std::vector<JointVector> Ur5eInverse(const Pose& base_from_flange, double q6_hint) {
  std::vector<JointVector> solutions;
  const Eigen::Matrix3d& r = base_from_flange.linear();
  const Eigen::Vector3d p6 = base_from_flange.translation();
  if (!p6.allFinite() || !r.allFinite()) return solutions;
  // Joint 1: the wrist centre (origin of frame 5) lies d4 off the arm's plane:
  // p5 . z1 = d4 with z1 = (sin q1, -cos q1, 0).
  const Eigen::Vector3d p5 = p6 - kD6 * r.col(2);
  const double rho = std::hypot(p5.x(), p5.y());
  if (!(rho > 0)) return solutions;
  auto shoulder = SafeAcos(kD4 / rho);
  if (!shoulder) return solutions;
  const double phi = std::atan2(p5.y(), p5.x());
  for (double s1sign : {1.0, -1.0}) {
    const double q1 = Wrap(phi + M_PI / 2 + s1sign * *shoulder);
    const double c1 = std::cos(q1), s1 = std::sin(q1);
    // Joint 5: z1^T R is the z row of R_16 = (s5 c6, -s5 s6, c5). Its last entry
    // equals (p6 . z1 - d4) / d6; the first two give |s5|. atan2 of both stays
    // accurate near the wrist singularity where acos(c5) would not.
    const double a = s1 * r(0, 0) - c1 * r(1, 0);  // s5 c6
    const double b = s1 * r(0, 1) - c1 * r(1, 1);  // -s5 s6
    const double c5 = s1 * r(0, 2) - c1 * r(1, 2);
    const double abs_s5 = std::hypot(a, b);
    for (double s5sign : {1.0, -1.0}) {
      const double q5 = std::atan2(s5sign * abs_s5, c5);
      const double s5 = s5sign * abs_s5;
      double q6 = q6_hint;
      if (abs_s5 > kWristSingular) q6 = std::atan2(-b / s5, a / s5);
      q6 = Wrap(q6);
      // Joints 2-4: a planar arm in frame 1. T_14 = A1^-1 T A6^-1 A5^-1.
      const Pose t14 = LinkTransform(0, q1).inverse() * base_from_flange * LinkTransform(5, q6).inverse() *
                       LinkTransform(4, q5).inverse();
      const Eigen::Vector2d pxy = t14.translation().head<2>();
      auto elbow = SafeAcos((pxy.squaredNorm() - kA2 * kA2 - kA3 * kA3) / (2 * kA2 * kA3));
      if (!elbow) continue;
      for (double s3sign : {1.0, -1.0}) {
        const double q3 = s3sign * *elbow;
        const double q2 = std::atan2(pxy.y(), pxy.x()) - std::atan2(kA3 * std::sin(q3), kA2 + kA3 * std::cos(q3));
        // R_14 = Rz(q2 + q3 + q4) Rx(pi/2): the x column gives the sum.
        const double sum = std::atan2(t14.linear()(1, 0), t14.linear()(0, 0));
        JointVector q;
        q << q1, Wrap(q2), Wrap(q3), Wrap(sum - q2 - q3), q5, q6;
        solutions.push_back(q);
        if (*elbow == 0) break;  // both elbow branches coincide
      }
      if (abs_s5 <= kWristSingular) break;  // both wrist branches coincide
    }
  }
  return solutions;
}

std::optional<JointVector> Ur5eNearestSolution(const Pose& base_from_flange, const JointVector& previous,
                                               const Ur5eLimits& limits, bool* limits_violated) {
  if (limits_violated) *limits_violated = false;
  std::vector<JointVector> solutions = Ur5eInverse(base_from_flange, previous[5]);
  if (solutions.empty()) return std::nullopt;
  std::optional<JointVector> best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const JointVector& s : solutions) {
    JointVector q;
    bool inside = true;
    for (int j = 0; j < 6; ++j) {
      // The whole-turn shift of s[j] nearest previous[j] that fits the limits.
      double candidate = s[j] + 2 * M_PI * std::round((previous[j] - s[j]) / (2 * M_PI));
      double best_j = std::numeric_limits<double>::quiet_NaN();
      for (double shift : {0.0, -2 * M_PI, 2 * M_PI}) {
        double v = candidate + shift;
        if (v < limits.position_min_rad[j] || v > limits.position_max_rad[j]) continue;
        if (std::isnan(best_j) || std::abs(v - previous[j]) < std::abs(best_j - previous[j])) best_j = v;
      }
      if (std::isnan(best_j)) {
        inside = false;
        break;
      }
      q[j] = best_j;
    }
    if (!inside) continue;
    double distance = (q - previous).norm();
    if (distance < best_distance) {
      best_distance = distance;
      best = q;
    }
  }
  if (!best && limits_violated) *limits_violated = true;
  return best;
}

std::string JointPathProblem::Describe() const {
  switch (kind) {
    case Kind::kUnreachable: return "the pose is out of the UR5e's reach";
    case Kind::kPositionLimit:
      return std::string("every solution puts a joint outside its limits (") + Ur5eJointName(joint) + " at " +
             Deg(value) + " deg, limit " + Deg(limit) + " deg)";
    case Kind::kSpeedLimit: {
      std::string text = !std::isfinite(value)
                             ? std::string(Ur5eJointName(joint)) + " turns " + Deg(std::abs(delta_rad)) +
                                   " deg in no time, limit " + Deg(limit) + " deg/s"
                             : std::string(Ur5eJointName(joint)) + " needs " + Deg(value) + " deg/s, limit " +
                                   Deg(limit) + " deg/s";
      if (wound_joint >= 0) {
        text += "; the arm changes configuration: " + std::string(Ur5eJointName(wound_joint)) + " would reach " +
                Deg(wound_value) + " deg, past its limit " + Deg(wound_limit) + " deg";
      }
      return text;
    }
  }
  return "";
}

namespace {

// A joint past its position limit: which, its angle and the limit.
struct BrokenLimit {
  int joint = -1;
  double value = 0, limit = 0;
};

// The first joint that the nearest solution without position limits puts past a limit,
// if any: what keeps the arm from the nearest solution.
std::optional<BrokenLimit> LimitOfNearest(const Pose& base_from_flange, const JointVector& previous,
                                          const Ur5eLimits& limits) {
  Ur5eLimits open = limits;
  open.position_min_rad.setConstant(-1e9);
  open.position_max_rad.setConstant(1e9);
  const std::optional<JointVector> free = Ur5eNearestSolution(base_from_flange, previous, open);
  if (!free) return std::nullopt;
  for (int j = 0; j < 6; ++j) {
    const double v = (*free)[j];
    if (v < limits.position_min_rad[j]) return BrokenLimit{j, v, limits.position_min_rad[j]};
    if (v > limits.position_max_rad[j]) return BrokenLimit{j, v, limits.position_max_rad[j]};
  }
  return std::nullopt;
}

}  // namespace

JointPath SolveJointPath(const std::vector<RobotWaypoint>& waypoints, const JointVector& start,
                         const Ur5eLimits& limits) {
  limits.Check();
  JointPath path;
  JointVector previous = start;
  double worst_ratio = 0;
  for (size_t i = 0; i < waypoints.size(); ++i) {
    bool limits_violated = false;
    auto q = Ur5eNearestSolution(waypoints[i].base_from_flange, previous, limits, &limits_violated);
    if (!q) {
      JointPathProblem problem;
      problem.waypoint = i;
      if (limits_violated) {
        problem.kind = JointPathProblem::Kind::kPositionLimit;
        if (auto broken = LimitOfNearest(waypoints[i].base_from_flange, previous, limits)) {
          problem.joint = broken->joint;
          problem.value = broken->value;
          problem.limit = broken->limit;
        }
      }
      path.failure = problem;
      return path;
    }
    if (i > 0) {
      const double dt = waypoints[i].t_s - waypoints[i - 1].t_s;
      // Whether a position limit forced the step (solved once, at its first violation).
      std::optional<std::optional<BrokenLimit>> wound;
      for (int j = 0; j < 6; ++j) {
        const double delta = (*q)[j] - previous[j];
        if (delta == 0) continue;
        const double speed = dt > 0 ? std::abs(delta) / dt : std::numeric_limits<double>::infinity();
        path.max_speed_rad_s[j] = std::max(path.max_speed_rad_s[j], speed);
        if (speed > limits.speed_max_rad_s[j]) {
          JointPathProblem problem;
          problem.kind = JointPathProblem::Kind::kSpeedLimit;
          problem.waypoint = i;
          problem.joint = j;
          problem.value = speed;
          problem.limit = limits.speed_max_rad_s[j];
          problem.delta_rad = delta;
          if (!wound) wound = LimitOfNearest(waypoints[i].base_from_flange, previous, limits);
          if (*wound) {
            problem.wound_joint = (*wound)->joint;
            problem.wound_value = (*wound)->value;
            problem.wound_limit = (*wound)->limit;
          }
          if (!path.first_speed_violation) path.first_speed_violation = problem;
          const double ratio = speed / limits.speed_max_rad_s[j];
          if (ratio > worst_ratio) {
            worst_ratio = ratio;
            path.worst_speed_violation = problem;
          }
        }
      }
      // Count steps, not joints: one step may break several limits.
      bool any = false;
      for (int j = 0; j < 6 && !any; ++j) {
        const double delta = std::abs((*q)[j] - previous[j]);
        any = delta > 0 && (dt <= 0 || delta / dt > limits.speed_max_rad_s[j]);
      }
      if (any) ++path.speed_violations;
    }
    path.t_s.push_back(waypoints[i].t_s);
    path.q.push_back(*q);
    previous = *q;
  }
  return path;
}

}  // namespace lt

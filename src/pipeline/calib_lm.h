// A small dense Levenberg–Marquardt solver for calibration problems (a few
// hundred parameters at most) and the covariance of its solution.
//
// The problem is r(x) -> residuals, minimised in the sum of squares
// cost = Σ r². Parameters may live on a manifold (rotations): the solver works
// on a tangent step δ and moves by x ⊞ δ (`plus`, default x + δ); the Jacobian
// is J = ∂r(x ⊞ δ)/∂δ at δ = 0. Without an analytic Jacobian it is taken by
// central differences with a step per tangent parameter.
//
// Damping follows Marquardt (λ·diag(JᵀJ), so the step does not depend on the
// parameters' units) with Nielsen's update of λ. It stops when the gradient is
// orthogonal to the residual to 1e-10 (max_i |J_iᵀ r| / (|J_i| |r|)), when the
// predicted decrease falls below 1e-14 of the cost, when the cost is exactly
// zero, or when no step along the gradient lowers the cost any more (the cost
// has reached its floating-point floor: reported as converged, with a message).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace lt {

struct LmProblem {
  int num_params = 0;     // tangent dimension (length of δ)
  int num_residuals = 0;  // length of r
  // r(x). Returns false when x is outside the model's domain (a point behind
  // the camera): the step that led there is rejected.
  std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd* r)> residuals;
  // x ⊞ δ; empty: x + δ (then x has num_params entries).
  std::function<Eigen::VectorXd(const Eigen::VectorXd& x, const Eigen::VectorXd& delta)> plus;
  // J (num_residuals x num_params) at x; empty: central differences with diff_step.
  std::function<bool(const Eigen::VectorXd& x, Eigen::MatrixXd* jacobian)> jacobian;
  Eigen::VectorXd diff_step;  // per tangent parameter, for the numeric Jacobian
  std::vector<std::string> names;  // per tangent parameter, for messages
};

struct LmOptions {
  int max_iterations = 200;
  double initial_lambda = 1e-3;
};

struct LmSummary {
  bool ok = false;  // false: the start could not be evaluated (see message)
  bool converged = false;
  Eigen::VectorXd x;
  Eigen::VectorXd residuals;  // at x
  Eigen::MatrixXd jacobian;   // at x
  double initial_cost = 0;
  double cost = 0;  // Σ r² at x
  int iterations = 0;
  std::string message;
};

LmSummary SolveLevenbergMarquardt(const LmProblem& problem, const Eigen::VectorXd& x0, const LmOptions& options = {});

// Central-difference Jacobian of `problem` at x (columns per tangent parameter).
bool NumericJacobian(const LmProblem& problem, const Eigen::VectorXd& x, Eigen::MatrixXd* jacobian);

// Covariance of the tangent parameters at an LM solution:
//   C = σ² (JᵀJ)⁻¹ with σ² = cost / (m − n)   (the a-posteriori variance factor).
// Refused (ok = false with a reason) when there is no redundancy (m <= n), when
// a parameter has no effect on the residuals, or when JᵀJ (scaled to unit
// diagonal) has a condition number above max_condition: then the reason names
// the parameters that take part in the unobservable direction.
struct LmCovariance {
  bool ok = false;
  std::string reason;
  double sigma2 = 0;  // a-posteriori variance of one residual
  int dof = 0;        // m − n
  Eigen::MatrixXd covariance;
  Eigen::VectorXd stddev;  // sqrt of the diagonal
};

LmCovariance EstimateCovariance(const LmSummary& solution, const std::vector<std::string>& names,
                                double max_condition = 1e14);

}  // namespace lt

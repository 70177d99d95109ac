#include "pipeline/calib_lm.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"

namespace lt {

namespace {

Eigen::VectorXd Plus(const LmProblem& p, const Eigen::VectorXd& x, const Eigen::VectorXd& delta) {
  return p.plus ? p.plus(x, delta) : Eigen::VectorXd(x + delta);
}

bool AllFinite(const Eigen::VectorXd& v) { return v.allFinite(); }

bool Evaluate(const LmProblem& p, const Eigen::VectorXd& x, Eigen::VectorXd* r) {
  r->resize(p.num_residuals);
  return p.residuals(x, r) && r->size() == p.num_residuals && AllFinite(*r);
}

bool Jacobian(const LmProblem& p, const Eigen::VectorXd& x, Eigen::MatrixXd* j) {
  bool ok = p.jacobian ? p.jacobian(x, j) : NumericJacobian(p, x, j);
  return ok && j->rows() == p.num_residuals && j->cols() == p.num_params && j->allFinite();
}

// max_i |J_iᵀ r| / (|J_i| |r|): the cosine between the residual and the
// direction of each parameter. Zero at a stationary point, whatever the units.
double GradientCosine(const Eigen::MatrixXd& j, const Eigen::VectorXd& r) {
  const double rn = r.norm();
  if (rn == 0) return 0;
  double worst = 0;
  for (int i = 0; i < j.cols(); ++i) {
    const double cn = j.col(i).norm();
    if (cn == 0) continue;
    worst = std::max(worst, std::abs(j.col(i).dot(r)) / (cn * rn));
  }
  return worst;
}

std::string ParamName(const std::vector<std::string>& names, int i) {
  return i < int(names.size()) ? names[size_t(i)] : "parameter " + std::to_string(i);
}

}  // namespace

bool NumericJacobian(const LmProblem& p, const Eigen::VectorXd& x, Eigen::MatrixXd* j) {
  if (p.diff_step.size() != p.num_params) return false;
  j->resize(p.num_residuals, p.num_params);
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(p.num_params), rp, rm;
  for (int i = 0; i < p.num_params; ++i) {
    const double h = p.diff_step[i];
    delta[i] = h;
    const bool okp = Evaluate(p, Plus(p, x, delta), &rp);
    delta[i] = -h;
    const bool okm = Evaluate(p, Plus(p, x, delta), &rm);
    delta[i] = 0;
    if (!okp || !okm) return false;
    j->col(i) = (rp - rm) / (2.0 * h);
  }
  return true;
}

LmSummary SolveLevenbergMarquardt(const LmProblem& p, const Eigen::VectorXd& x0, const LmOptions& options) {
  LmSummary s;
  s.x = x0;
  if (!Evaluate(p, s.x, &s.residuals)) {
    s.message = "the residuals cannot be evaluated at the starting point";
    return s;
  }
  if (!Jacobian(p, s.x, &s.jacobian)) {
    s.message = "the Jacobian cannot be evaluated at the starting point";
    return s;
  }
  s.ok = true;
  s.cost = s.initial_cost = s.residuals.squaredNorm();
  const int n = p.num_params;
  double lambda = options.initial_lambda, nu = 2.0;
  Eigen::MatrixXd a = s.jacobian.transpose() * s.jacobian;
  Eigen::VectorXd g = s.jacobian.transpose() * s.residuals;
  Eigen::VectorXd r_new;
  for (s.iterations = 0; s.iterations < options.max_iterations; ++s.iterations) {
    if (s.cost == 0 || GradientCosine(s.jacobian, s.residuals) < 1e-10) {
      s.converged = true;
      s.message = "gradient orthogonal to the residuals";
      return s;
    }
    Eigen::VectorXd diag = a.diagonal();
    const double floor = std::max(diag.maxCoeff(), 1e-300) * 1e-15;
    for (int i = 0; i < n; ++i) diag[i] = std::max(diag[i], floor);
    Eigen::MatrixXd damped = a;
    damped.diagonal() += lambda * diag;
    const Eigen::VectorXd delta = damped.ldlt().solve(-g);
    const double predicted = -(2.0 * delta.dot(g) + delta.dot(a * delta));
    if (!delta.allFinite() || !(predicted > 0)) {
      lambda *= nu;
      nu *= 2;
    } else if (predicted <= 1e-14 * s.cost) {
      s.converged = true;
      s.message = "predicted decrease below 1e-14 of the cost";
      return s;
    } else {
      const Eigen::VectorXd x_new = Plus(p, s.x, delta);
      const bool ok = Evaluate(p, x_new, &r_new);
      const double cost_new = ok ? r_new.squaredNorm() : HUGE_VAL;
      const double rho = (s.cost - cost_new) / predicted;
      if (ok && rho > 0) {
        Eigen::MatrixXd j_new;
        if (!Jacobian(p, x_new, &j_new)) {
          lambda *= nu;
          nu *= 2;
        } else {
          s.x = x_new;
          s.residuals = r_new;
          s.cost = cost_new;
          s.jacobian = std::move(j_new);
          a = s.jacobian.transpose() * s.jacobian;
          g = s.jacobian.transpose() * s.residuals;
          lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
          nu = 2.0;
        }
      } else {
        lambda *= nu;
        nu *= 2;
      }
    }
    if (lambda > 1e20) {
      // No step along the (damped) gradient lowers the cost: the cost is at its
      // floating-point floor around a minimum.
      s.converged = true;
      s.message = "no further decrease possible (cost at its numerical floor)";
      return s;
    }
  }
  s.message = "stopped after " + std::to_string(options.max_iterations) + " iterations";
  return s;
}

LmCovariance EstimateCovariance(const LmSummary& solution, const std::vector<std::string>& names,
                                double max_condition) {
  LmCovariance c;
  const Eigen::MatrixXd& j = solution.jacobian;
  const int m = int(j.rows()), n = int(j.cols());
  c.dof = m - n;
  if (c.dof <= 0) {
    c.reason = "no redundancy: " + std::to_string(m) + " residuals for " + std::to_string(n) + " parameters";
    return c;
  }
  c.sigma2 = solution.cost / c.dof;
  const Eigen::MatrixXd a = j.transpose() * j;
  Eigen::VectorXd scale(n);
  for (int i = 0; i < n; ++i) {
    if (!(a(i, i) > 0)) {
      c.reason = ParamName(names, i) + " has no effect on the residuals";
      return c;
    }
    scale[i] = 1.0 / std::sqrt(a(i, i));
  }
  const Eigen::MatrixXd scaled = scale.asDiagonal() * a * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
  const Eigen::VectorXd& ev = eig.eigenvalues();  // ascending
  if (eig.info() != Eigen::Success || !(ev[0] > ev[n - 1] / max_condition)) {
    // Name the parameters of the (nearly) unobservable direction.
    const Eigen::VectorXd v = eig.eigenvectors().col(0).cwiseAbs();
    std::vector<int> order(static_cast<size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int x, int y) { return v[x] > v[y]; });
    std::string which;
    for (int k = 0; k < n && k < 4 && v[order[size_t(k)]] > 0.1; ++k) {
      which += (k ? ", " : "") + ParamName(names, order[size_t(k)]);
    }
    c.reason = "parameters not observable from these data (normal matrix condition number " +
               FormatNumber(ev[n - 1] / std::max(ev[0], 0.0)) + "); the weak direction involves " + which;
    return c;
  }
  const Eigen::MatrixXd inv = eig.eigenvectors() * ev.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  c.covariance = c.sigma2 * (scale.asDiagonal() * inv * scale.asDiagonal());
  c.stddev = c.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  c.ok = true;
  return c;
}

}  // namespace lt

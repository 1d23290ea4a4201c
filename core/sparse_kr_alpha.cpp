#include "core/sparse_kr_alpha.hpp"

#include "core/constraint_set.hpp"       // snap_walls
#include "core/implicit_integrator.hpp"  // solve_listed_augmented
#include "core/parameter_error.hpp"
#include "core/sparse_constraints.hpp"

namespace impactid {

void SparseKrAlphaExplicit::respond(const SparseSystem& system, bool start, Eigen::VectorXd& a,
                                    Eigen::VectorXd& w) const {
  if (start) {
    w = a;                    // the same size: no allocation
    mass_.solve_in_place(a);  // M⁻¹·f
    d_.solve_in_place(w);     // D⁻¹·f
    return;
  }
  mass_.solve_in_place(a);
  multiply(d_matrix_, a, w);
  e_.solve_in_place(w);
  a.swap(w);  // a = E⁻¹·D·M⁻¹·f
  multiply(system.mass, a, w);
  d_.solve_in_place(w);  // D⁻¹·M·a
}

bool SparseKrAlphaExplicit::set_up(const SparseSystem& system, ContactProblem& problem) {
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  Eigen::MatrixXd g(m, m);
  Eigen::VectorXd unit(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    unit.setZero();
    unit[k] = 1.0;
    response_a_.setZero();
    add_constraint_forces(system.constraints, unit, 1.0, response_a_);
    respond(system, problem.start, response_a_, response_w_);
    for (Eigen::Index j = 0; j < m; ++j) {
      g(j, k) = problem.scale *
                constraint_row(system.constraints[static_cast<std::size_t>(j)], response_w_);
    }
  }
  problem.delassus.resize(m, m);
  if (m == 0) return true;
  // Symmetric in exact arithmetic when the damping is proportional to M and K (core/
  // kr_alpha.hpp); the contact solver's Cholesky needs it exactly so. KrAlphaExplicit's test.
  const double asymmetry = (g - g.transpose()).cwiseAbs().maxCoeff();
  if (!(asymmetry <= 1e-9 * g.cwiseAbs().maxCoeff())) {
    failure_ = "the contact operator of the constraint list is not symmetric (relative asymmetry " +
               format_value(asymmetry / g.cwiseAbs().maxCoeff()) +
               "): kr-alpha takes a damping proportional to M and K";
    return false;
  }
  problem.delassus = 0.5 * (g + g.transpose());
  if (contact_.law == ContactLaw::augmented_lagrangian) {
    problem.penalized = problem.delassus;
    problem.penalized.diagonal() += compliance_;
  }
  return true;
}

bool SparseKrAlphaExplicit::initialize(const SparseSystem& system,
                                       const KrAlphaCoefficients& coefficients, double dt,
                                       State& start, const ContactPenalties& contact) {
  failure_.clear();
  contact_ = contact;
  iterations_ = unconverged_ = 0;
  if (contact_.law == ContactLaw::penalty) {
    failure_ = "contact = penalty is not available (core/kr_alpha.hpp says why)";
    return false;
  }
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  if (contact_.law == ContactLaw::augmented_lagrangian) {
    compliance_.resize(m);
    for (Eigen::Index j = 0; j < m; ++j) {
      compliance_[j] = 1.0 / contact_.listed[static_cast<std::size_t>(j)];
    }
    shift_.resize(m);
    shifted_.resize(m);
  }
  c_ = coefficients;
  dt_ = dt;
  const double c_weight = c_.gamma * dt, k_weight = c_.beta * dt * dt;
  d_matrix_ = system.mass + k_weight * system.stiffness;
  SparseMatrix e_matrix =
      (1.0 - c_.alpha_m) * system.mass + ((1.0 - c_.alpha_f) * k_weight) * system.stiffness;
  if (system.has_damping()) {
    d_matrix_ += c_weight * system.damping;
    e_matrix += ((1.0 - c_.alpha_f) * c_weight) * system.damping;
  }
  if (!mass_.factor(system.mass)) {
    failure_ = pivot_failure("the mass matrix", mass_);
    return false;
  }
  if (!d_.factor(d_matrix_)) {
    failure_ = pivot_failure("the matrix M + gamma*dt*C + beta*dt^2*K", d_);
    return false;
  }
  if (!e_.factor(e_matrix)) {
    failure_ =
        pivot_failure("the matrix (1 - alpha_m)*M + (1 - alpha_f)*(gamma*dt*C + beta*dt^2*K)", e_);
    return false;
  }
  const Eigen::Index n = system.size();
  response_a_.resize(n);
  response_w_.resize(n);
  start_problem_.start = true;
  start_problem_.scale = 0.5 * dt * dt;
  step_problem_.start = false;
  step_problem_.scale = dt * dt * (0.5 + c_.gamma);
  if (!set_up(system, start_problem_) || !set_up(system, step_problem_)) return false;
  violation_.resize(m);
  forces_.setZero(m);
  lcp_.resize(static_cast<int>(m));
  r_.resize(n);
  y_.resize(n);
  w_.resize(n);

  // The start (core/kr_alpha.hpp): u₁ = u₀ + Δt·v₀ + Δt²/2·α1·a₀, its contact by the start's
  // problem.
  multiply(system.mass, start.a, w_);
  d_.solve_in_place(w_);  // α1·a₀
  u_next_ = start.u + dt * start.v + start_problem_.scale * w_;
  enforce(system, start_problem_, start.a, u_next_, start);
  v_hat_ = start.v - (c_.gamma * dt) * w_;
  return true;
}

bool SparseKrAlphaExplicit::enforce(const SparseSystem& system, const ContactProblem& problem,
                                    Eigen::VectorXd& a, Eigen::VectorXd& next, State& at) {
  const auto m = static_cast<int>(system.constraints.size());
  for (int j = 0; j < m; ++j) {
    const Constraint& con = system.constraints[static_cast<std::size_t>(j)];
    double g = -con.gap;  // KrAlphaExplicit's order of operations
    if (con.plus >= 0) g += next[con.plus];
    if (con.minus >= 0) g -= next[con.minus];
    violation_[j] = g;
  }
  if (contact_.lagrange()) {
    solve_contact_lcp(problem.delassus.data(), violation_.data(), m, forces_.data(), lcp_);
  } else if (m > 0 && violation_.maxCoeff() > 0.0) {
    count(solve_listed_augmented(problem.delassus, problem.penalized, compliance_, violation_,
                                 contact_, forces_, shift_, shifted_, &lcp_));
  } else {
    forces_.setZero();
  }
  at.multipliers = forces_;  // the same size: no allocation
  at.lambda = 0.0;           // the list's are in multipliers
  if (!(m > 0 && forces_.maxCoeff() > 0.0)) return false;
  response_a_.setZero();
  add_constraint_forces(system.constraints, forces_, 1.0, response_a_);
  respond(system, problem.start, response_a_, response_w_);
  a -= response_a_;
  w_ -= response_w_;
  next -= problem.scale * response_w_;
  if (contact_.lagrange()) snap_walls(system.constraints, forces_, next);
  return true;
}

void SparseKrAlphaExplicit::count(const ContactIterations& iterations) {
  iterations_ += iterations.iterations;
  if (!iterations.converged) ++unconverged_;
}

bool SparseKrAlphaExplicit::step(const SparseSystem& system, State& state) {
  const Eigen::Index n = system.size();
  const double af = c_.alpha_f, dt = dt_;
  const bool damped = system.has_damping();

  // KrAlphaExplicit::step's operations. r = −K·u_{1−α_f} − C·v_{1−α_f}: the α_f parts at t
  // first, while the state still holds them.
  r_.setZero();
  multiply_add(system.stiffness, -af, state.u, r_);
  if (damped) multiply_add(system.damping, -af, v_hat_, r_);
  // The explicit u₁ (fixed, with its contact, by the last equilibrium) and v̂₁ = v̂₀ + Δt·α1·a₀.
  state.u = u_next_;
  for (Eigen::Index i = 0; i < n; ++i) v_hat_[i] += dt * w_[i];
  multiply_add(system.stiffness, -(1.0 - af), state.u, r_);
  if (damped) multiply_add(system.damping, -(1.0 - af), v_hat_, r_);

  // a₁ = a₀ + E⁻¹·D·(M⁻¹·r − a₀).
  mass_.solve_in_place(r_);
  for (Eigen::Index i = 0; i < n; ++i) r_[i] -= state.a[i];
  multiply(d_matrix_, r_, y_);
  e_.solve_in_place(y_);
  for (Eigen::Index i = 0; i < n; ++i) state.a[i] += y_[i];

  // α1·a₁ and the contact-free u₂ = u₁ + Δt·v₁ + Δt²(½ + γ)·α1·a₁.
  multiply(system.mass, state.a, w_);
  d_.solve_in_place(w_);
  const double scale = step_problem_.scale;
  for (Eigen::Index i = 0; i < n; ++i) u_next_[i] = state.u[i] + dt * v_hat_[i] + scale * w_[i];
  const bool pushing = enforce(system, step_problem_, state.a, u_next_, state);
  // The sample's velocity: v̂ lags u by γΔt.
  const double lead = c_.gamma * dt;
  for (Eigen::Index i = 0; i < n; ++i) state.v[i] = v_hat_[i] + lead * w_[i];
  state.t += dt;
  return pushing;
}

double SparseKrAlphaExplicit::energy(const SparseSystem& system, const State& state) {
  const Eigen::Index n = system.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    r_[i] = (u_next_[i] - state.u[i]) / dt_;
    y_[i] = 0.5 * (state.u[i] + u_next_[i]);
  }
  return 0.5 * quadratic_form(system.mass, r_) + 0.5 * quadratic_form(system.stiffness, y_);
}

}  // namespace impactid

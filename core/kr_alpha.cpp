#include "core/kr_alpha.hpp"

#include <cmath>

#include "core/constraint_set.hpp"
#include "core/contact_lcp.hpp"
#include "core/implicit_integrator.hpp"  // solve_listed_augmented
#include "core/parameter_error.hpp"
#include "core/two_wall_contact.hpp"

namespace impactid {
namespace {

// The rows [begin, end) outside which a column is exactly zero.
std::pair<Eigen::Index, Eigen::Index> non_zero_rows(const Eigen::VectorXd& column) {
  const Eigen::Index n = column.size();
  Eigen::Index begin = 0, end = n;
  while (begin < n && column[begin] == 0.0) ++begin;
  while (end > begin && column[end - 1] == 0.0) --end;
  return {begin, end};
}

}  // namespace

void KrAlphaExplicit::respond(const SecondOrderSystem& system, bool start,
                              const Eigen::VectorXd& force, Eigen::VectorXd& a,
                              Eigen::VectorXd& w) const {
  a = force;
  mass_.solve_in_place(a);  // M⁻¹·f
  if (start) {
    w = force;
    d_.solve_in_place(w);  // D⁻¹·f
    return;
  }
  Eigen::VectorXd y(a.size());
  d_matrix_.multiply(a, y);
  e_.solve_in_place(y);  // E⁻¹·D·M⁻¹·f
  a = y;
  w.resize(a.size());
  system.mass.multiply(a, w);
  d_.solve_in_place(w);  // D⁻¹·M·a
}

bool KrAlphaExplicit::set_up(const SecondOrderSystem& system, bool start,
                             ContactResponse& response) {
  const Eigen::Index n = system.size();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd force = zero;
  force[system.contact_dof] = 1.0;
  respond(system, start, force, response.a_main, response.w_main);
  if (system.has_far_contact()) {
    force = zero;
    force[system.far_contact_dof] = 1.0;
    respond(system, start, force, response.a_far, response.w_far);
  } else {
    response.a_far.resize(0);
    response.w_far.resize(0);
  }
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  response.a_list.setZero(n, m);
  response.w_list.setZero(n, m);
  response.rows_a.assign(static_cast<std::size_t>(m), {0, 0});
  response.rows_w.assign(static_cast<std::size_t>(m), {0, 0});
  response.delassus.setZero(m, m);
  Eigen::VectorXd a, w;
  for (Eigen::Index k = 0; k < m; ++k) {
    const Constraint& c = system.constraints[static_cast<std::size_t>(k)];
    force = zero;
    if (c.plus >= 0) force[c.plus] += 1.0;
    if (c.minus >= 0) force[c.minus] -= 1.0;
    respond(system, start, force, a, w);
    response.a_list.col(k) = a;
    response.w_list.col(k) = w;
    response.rows_a[static_cast<std::size_t>(k)] = non_zero_rows(a);
    response.rows_w[static_cast<std::size_t>(k)] = non_zero_rows(w);
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    const Constraint& c = system.constraints[static_cast<std::size_t>(j)];
    for (Eigen::Index k = 0; k < m; ++k) {
      double g = 0.0;
      if (c.plus >= 0) g += response.w_list(c.plus, k);
      if (c.minus >= 0) g -= response.w_list(c.minus, k);
      response.delassus(j, k) = scale_ * g;
    }
  }
  if (m == 0) return true;
  // Symmetric in exact arithmetic when the damping is proportional to M and K (the header); the
  // contact solver's Cholesky needs it exactly so.
  const Eigen::MatrixXd& g = response.delassus;
  const double asymmetry = (g - g.transpose()).cwiseAbs().maxCoeff();
  if (!(asymmetry <= 1e-9 * g.cwiseAbs().maxCoeff())) {
    failure_ = "the contact operator of the constraint list is not symmetric (relative asymmetry " +
               format_value(asymmetry / g.cwiseAbs().maxCoeff()) +
               "): kr-alpha takes a damping proportional to M and K on each body";
    return false;
  }
  response.delassus = (0.5 * (g + g.transpose())).eval();
  if (contact_.law == ContactLaw::augmented_lagrangian) {
    response.penalized = response.delassus;
    response.penalized.diagonal() += compliance_;
  }
  return true;
}

bool KrAlphaExplicit::initialize(const SecondOrderSystem& system,
                                 const KrAlphaCoefficients& coefficients, double dt, State& start,
                                 const ContactPenalties& contact) {
  failure_.clear();
  contact_ = contact;
  iterations_ = unconverged_ = 0;
  const auto constraints = static_cast<Eigen::Index>(system.constraints.size());
  if (contact_.law == ContactLaw::augmented_lagrangian) {
    compliance_.resize(constraints);
    for (Eigen::Index j = 0; j < constraints; ++j) {
      compliance_[j] = 1.0 / contact_.listed[static_cast<std::size_t>(j)];
    }
    shift_.resize(constraints);
    shifted_.resize(constraints);
  }
  c_ = coefficients;
  dt_ = dt;
  scale_ = dt * dt * (0.5 + c_.gamma);
  const double c_weight = c_.gamma * dt, k_weight = c_.beta * dt * dt;
  d_matrix_ =
      system.mass.combined(1.0, system.damping, c_weight).combined(1.0, system.stiffness, k_weight);
  const Tridiagonal e_matrix =
      system.mass.combined(1.0 - c_.alpha_m, system.damping, (1.0 - c_.alpha_f) * c_weight)
          .combined(1.0, system.stiffness, (1.0 - c_.alpha_f) * k_weight);
  if (!mass_.factor(system.mass)) {
    failure_ = "singular mass matrix";
    return false;
  }
  if (!d_.factor(d_matrix_) || !e_.factor(e_matrix)) {
    failure_ = "singular matrix M + gamma*dt*C + beta*dt^2*K";
    return false;
  }
  scale_ = 0.5 * dt * dt;  // the start's (initialize() below)
  if (!set_up(system, true, start_response_)) return false;
  scale_ = dt * dt * (0.5 + c_.gamma);
  if (!set_up(system, false, step_response_)) return false;
  const Eigen::Index n = system.size();
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  violation_.resize(m);
  forces_.resize(m);
  scaled_forces_.resize(m);
  r_.resize(n);
  y_.resize(n);
  w_.resize(n);

  // The start (the header): u₁ = u₀ + Δt·v̂₀ + s·α1·a₀ with v̂₀ = v₀ − γΔt·α1·a₀ is
  // u₀ + Δt·v₀ + Δt²/2·α1·a₀, so the start's contact moves it by Δt²/2 per unit of α1·a₀.
  system.mass.multiply(start.a, w_);
  d_.solve_in_place(w_);  // α1·a₀
  const double start_scale = 0.5 * dt * dt;
  u_next_ = start.u + dt * start.v + start_scale * w_;
  scale_ = start_scale;
  enforce(system, start_response_, start.a, u_next_, start);
  scale_ = dt * dt * (0.5 + c_.gamma);
  v_hat_ = start.v - (c_.gamma * dt) * w_;
  return true;
}

bool KrAlphaExplicit::enforce(const SecondOrderSystem& system, const ContactResponse& response,
                              Eigen::VectorXd& a, Eigen::VectorXd& next, State& at) {
  if (system.has_constraint_list()) {
    const auto m = static_cast<int>(system.constraints.size());
    for (int j = 0; j < m; ++j) {
      const Constraint& con = system.constraints[static_cast<std::size_t>(j)];
      double g = -con.gap;
      if (con.plus >= 0) g += next[con.plus];
      if (con.minus >= 0) g -= next[con.minus];
      violation_[j] = g;
    }
    if (contact_.lagrange()) {
      solve_contact_lcp(response.delassus.data(), violation_.data(), m, forces_.data());
    } else if (violation_.maxCoeff() > 0.0) {
      count(solve_listed_augmented(response.delassus, response.penalized, compliance_, violation_,
                                   contact_, forces_, shift_, shifted_));
    } else {
      forces_.setZero();
    }
    apply_constraint_forces(response.a_list, response.rows_a, forces_, a);
    apply_constraint_forces(response.w_list, response.rows_w, forces_, w_);
    scaled_forces_ = scale_ * forces_;
    apply_constraint_forces(response.w_list, response.rows_w, scaled_forces_, next);
    if (contact_.lagrange()) snap_walls(system.constraints, forces_, next);
    at.multipliers = forces_;  // the same size: no allocation
    at.lambda = 0.0;           // the list's are in multipliers
    return forces_.size() > 0 && forces_.maxCoeff() > 0.0;
  }
  const Eigen::Index contact = system.contact_dof;
  const double s = scale_;
  if (system.has_far_contact()) {
    const Eigen::Index far = system.far_contact_dof;
    TwoWallForces forces;
    if (contact_.lagrange()) {
      forces = solve_two_wall_contact(next[contact] - system.gap, -system.far_gap - next[far],
                                      s * response.w_main[contact], s * response.w_far[far],
                                      s * response.w_far[contact], s * response.w_main[far]);
    } else {
      ContactIterations iterations;
      forces = two_wall_contact_forces(
          next[contact] - system.gap, -system.far_gap - next[far], s * response.w_main[contact],
          s * response.w_far[far], s * response.w_far[contact], s * response.w_main[far],
          1.0 / contact_.main, 1.0 / contact_.far, contact_, iterations);
      count(iterations);
    }
    if (forces.main > 0.0) {
      a -= forces.main * response.a_main;
      w_ -= forces.main * response.w_main;
      next -= (s * forces.main) * response.w_main;
    }
    if (forces.far > 0.0) {
      a += forces.far * response.a_far;
      w_ += forces.far * response.w_far;
      next += (s * forces.far) * response.w_far;
    }
    if (contact_.lagrange()) {
      if (forces.main > 0.0) next[contact] = system.gap;  // exact, not a few ulps off
      if (forces.far > 0.0) next[far] = -system.far_gap;
    }
    at.lambda = forces.main;
    at.far_lambda = forces.far;
    return forces.main > 0.0 || forces.far > 0.0;
  }
  at.lambda = 0.0;
  if (!system.has_contact() || !(next[contact] > system.gap)) return false;
  double lambda = 0.0;
  if (contact_.lagrange()) {
    lambda = (next[contact] - system.gap) / (s * response.w_main[contact]);
  } else {
    ContactIterations iterations;
    lambda = single_contact_force(next[contact] - system.gap, s * response.w_main[contact],
                                  1.0 / contact_.main, contact_, iterations);
    count(iterations);
  }
  a -= lambda * response.a_main;
  w_ -= lambda * response.w_main;
  next -= (s * lambda) * response.w_main;
  if (contact_.lagrange()) next[contact] = system.gap;
  at.lambda = lambda;
  return true;
}

void KrAlphaExplicit::count(const ContactIterations& iterations) {
  iterations_ += iterations.iterations;
  if (!iterations.converged) ++unconverged_;
}

bool KrAlphaExplicit::step(const SecondOrderSystem& system, State& state) {
  const Eigen::Index n = system.size();
  const double af = c_.alpha_f, dt = dt_;
  const bool damped = system.has_damping();

  // r = −K·u_{1−α_f} − C·v_{1−α_f}: the α_f parts at t first, while the state still holds them.
  r_.setZero();
  system.stiffness.multiply_add(-af, state.u, r_);
  if (damped) system.damping.multiply_add(-af, v_hat_, r_);
  // The explicit u₁ (fixed, with its contact, by the last equilibrium) and v̂₁ = v̂₀ + Δt·α1·a₀.
  state.u = u_next_;
  for (Eigen::Index i = 0; i < n; ++i) v_hat_[i] += dt * w_[i];
  system.stiffness.multiply_add(-(1.0 - af), state.u, r_);
  if (damped) system.damping.multiply_add(-(1.0 - af), v_hat_, r_);

  // a₁ = a₀ + E⁻¹·D·(M⁻¹·r − a₀).
  mass_.solve_in_place(r_);
  for (Eigen::Index i = 0; i < n; ++i) r_[i] -= state.a[i];
  d_matrix_.multiply(r_, y_);
  e_.solve_in_place(y_);
  for (Eigen::Index i = 0; i < n; ++i) state.a[i] += y_[i];

  // α1·a₁ and the contact-free u₂ = u₁ + Δt·v₁ + Δt²(½ + γ)·α1·a₁.
  system.mass.multiply(state.a, w_);
  d_.solve_in_place(w_);
  for (Eigen::Index i = 0; i < n; ++i) u_next_[i] = state.u[i] + dt * v_hat_[i] + scale_ * w_[i];
  const bool pushing = enforce(system, step_response_, state.a, u_next_, state);
  // The sample's velocity: v̂ lags u by γΔt (the header).
  const double lead = c_.gamma * dt;
  for (Eigen::Index i = 0; i < n; ++i) state.v[i] = v_hat_[i] + lead * w_[i];
  state.t += dt;
  return pushing;
}

double KrAlphaExplicit::energy(const SecondOrderSystem& system, const State& state) {
  const Eigen::Index n = system.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    r_[i] = (u_next_[i] - state.u[i]) / dt_;
    y_[i] = 0.5 * (state.u[i] + u_next_[i]);
  }
  return 0.5 * system.mass.quadratic_form(r_) + 0.5 * system.stiffness.quadratic_form(y_);
}

}  // namespace impactid

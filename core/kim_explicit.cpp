#include "core/kim_explicit.hpp"

#include <cmath>
#include <limits>

#include "core/constraint_set.hpp"
#include "core/contact_lcp.hpp"
#include "core/stable_step.hpp"
#include "core/two_wall_contact.hpp"

namespace impactid {

bool KimExplicit::initialize(const SecondOrderSystem& system,
                             const KimExplicitCoefficients& coefficients, double dt, State& start) {
  c_ = coefficients;
  dt_ = dt;
  const double p = c_.p, dt2 = dt * dt;
  scale_start_ = 0.5 * (p * dt) * (p * dt);
  scale_first_ = c_.up * dt2;
  scale_sample_ = c_.cu * c_.d1 * dt2;
  scale_next_ = scale_sample_ + p * c_.cv * c_.d1 * dt2 + 0.5 * p * p * dt2;

  // Ω_crit(p) over the Gershgorin bound on ω_max (nothing certified for a mass that is not
  // diagonal).
  const double bound = highest_frequency_squared_bound(system);
  const double omega_crit = kim_explicit_critical_omega(p);
  if (!std::isfinite(bound)) {
    stable_step_ = 0.0;
    within_limit_ = false;
  } else {
    stable_step_ =
        bound > 0.0 ? omega_crit / std::sqrt(bound) : std::numeric_limits<double>::infinity();
    within_limit_ = dt * dt * bound <= omega_crit * omega_crit * (1.0 + 1e-12);
  }

  if (!mass_.factor(system.mass)) return false;
  const Eigen::Index n = system.size();
  contact_influence_ = mass_.inverse_column(system.contact_dof);
  if (system.has_far_contact()) {
    far_influence_ = mass_.inverse_column(system.far_contact_dof);
  } else {
    far_influence_.resize(0);
  }
  set_up_constraints(system, mass_, 1.0, constraint_influence_, constraint_rows_, delassus_start_);
  delassus_first_ = scale_first_ * delassus_start_;
  delassus_sample_ = scale_sample_ * delassus_start_;
  delassus_next_ = scale_next_ * delassus_start_;
  delassus_start_ *= scale_start_;
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  violation_.resize(m);
  forces_.resize(m);
  scaled_forces_.resize(m);
  a0_.resize(n);
  u_predicted_.resize(n);
  v_predicted_.resize(n);

  if (system.has_constraint_list()) start.multipliers.resize(m);
  sub_ = start;  // sizes the stage's state
  u_next_ = start.u + (p * dt) * start.v + scale_start_ * start.a;
  clear_multipliers(start);
  if (enforce(system, scale_start_, delassus_start_, start.a, u_next_)) add_last(system, start);
  return true;
}

void KimExplicit::solve_acceleration(const SecondOrderSystem& system, const Eigen::VectorXd& u,
                                     const Eigen::VectorXd& v_predicted, Eigen::VectorXd& a) {
  a.setZero();
  system.stiffness.multiply_add(-1.0, u, a);
  if (system.has_damping()) system.damping.multiply_add(-1.0, v_predicted, a);
  mass_.solve_in_place(a);
}

bool KimExplicit::enforce(const SecondOrderSystem& system, double scale,
                          const Eigen::MatrixXd& delassus, Eigen::VectorXd& a,
                          Eigen::VectorXd& next) {
  main_ = 0.0;
  far_ = 0.0;
  if (system.has_constraint_list()) {
    const auto m = static_cast<int>(system.constraints.size());
    for (int j = 0; j < m; ++j) {
      const Constraint& con = system.constraints[static_cast<std::size_t>(j)];
      double g = -con.gap;
      if (con.plus >= 0) g += next[con.plus];
      if (con.minus >= 0) g -= next[con.minus];
      violation_[j] = g;
    }
    solve_contact_lcp(delassus.data(), violation_.data(), m, forces_.data());
    if (!(forces_.size() > 0 && forces_.maxCoeff() > 0.0)) return false;
    apply_constraint_forces(constraint_influence_, constraint_rows_, forces_, a);
    apply_last(system, scale, next);
    snap_walls(system.constraints, forces_, next);
    return true;
  }
  const Eigen::Index contact = system.contact_dof;
  if (system.has_far_contact()) {
    const Eigen::Index far = system.far_contact_dof;
    const TwoWallForces forces =
        solve_two_wall_contact(next[contact] - system.gap, -system.far_gap - next[far],
                               scale * contact_influence_[contact], scale * far_influence_[far],
                               scale * far_influence_[contact], scale * contact_influence_[far]);
    main_ = forces.main;
    far_ = forces.far;
    if (!(main_ > 0.0 || far_ > 0.0)) return false;
    apply_last(system, 1.0, a);
    apply_last(system, scale, next);
    if (main_ > 0.0) next[contact] = system.gap;  // exact, not a few ulps off
    if (far_ > 0.0) next[far] = -system.far_gap;
    return true;
  }
  if (!system.has_contact() || !(next[contact] > system.gap)) return false;
  main_ = (next[contact] - system.gap) / (scale * contact_influence_[contact]);
  apply_last(system, 1.0, a);
  apply_last(system, scale, next);
  next[contact] = system.gap;
  return true;
}

void KimExplicit::apply_last(const SecondOrderSystem& system, double factor, Eigen::VectorXd& x) {
  if (system.has_constraint_list()) {
    scaled_forces_ = factor * forces_;  // the same size: no allocation
    apply_constraint_forces(constraint_influence_, constraint_rows_, scaled_forces_, x);
    return;
  }
  if (main_ > 0.0) x -= (factor * main_) * contact_influence_;
  if (far_ > 0.0) x += (factor * far_) * far_influence_;
}

void KimExplicit::add_last(const SecondOrderSystem& system, State& at) const {
  if (system.has_constraint_list()) {
    at.multipliers += forces_;
    return;
  }
  at.lambda += main_;
  at.far_lambda += far_;
}

void KimExplicit::clear_multipliers(State& at) {
  at.lambda = 0.0;
  at.far_lambda = 0.0;
  at.multipliers.setZero();
}

double KimExplicit::divided_difference(Eigen::Index i, const State& state) const {
  return c_.d0 * a0_[i] + c_.dp * sub_.a[i] + c_.d1 * state.a[i];
}

void KimExplicit::correct(State& state) const {
  const Eigen::Index n = state.u.size();
  const double du = c_.cu * dt_ * dt_, dv = c_.cv * dt_;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = divided_difference(i, state);
    state.u[i] = u_predicted_[i] + du * d;
    state.v[i] = v_predicted_[i] + dv * d;
  }
}

void KimExplicit::correct_velocity(State& state) const {
  const Eigen::Index n = state.v.size();
  const double dv = c_.cv * dt_;
  for (Eigen::Index i = 0; i < n; ++i)
    state.v[i] = v_predicted_[i] + dv * divided_difference(i, state);
}

bool KimExplicit::step(const SecondOrderSystem& system, State& state) {
  const Eigen::Index n = system.size();
  const double p = c_.p, dt = dt_, first = p * dt;

  // Stage 1: equilibrium at t + pΔt, at the displacement the last stage fixed, with the velocity
  // predictor v₀ + pΔt·a₀.
  a0_ = state.a;
  sub_.u = u_next_;
  for (Eigen::Index i = 0; i < n; ++i) sub_.v[i] = state.v[i] + first * state.a[i];
  solve_acceleration(system, sub_.u, sub_.v, sub_.a);
  // The contact-free ũ₁ = u₀ + Δt·v₀ + Δt²·u0·a₀ + s₁·a_p; λ_p puts it on the walls.
  const double u0 = c_.u0 * dt * dt;
  for (Eigen::Index i = 0; i < n; ++i) {
    u_predicted_[i] = state.u[i] + dt * state.v[i] + u0 * a0_[i] + scale_first_ * sub_.a[i];
  }
  clear_multipliers(sub_);
  if (enforce(system, scale_first_, delassus_first_, sub_.a, u_predicted_)) add_last(system, sub_);
  sub_.t = state.t + first;

  // Stage 2: equilibrium at t + Δt, at ũ₁ with the velocity predictor ṽ₁.
  const double v0 = c_.v0 * dt, vp = c_.vp * dt;
  for (Eigen::Index i = 0; i < n; ++i) {
    v_predicted_[i] = state.v[i] + v0 * a0_[i] + vp * sub_.a[i];
  }
  solve_acceleration(system, u_predicted_, v_predicted_, state.a);
  correct(state);
  clear_multipliers(state);
  // λ₁: first the sample u₁ on the walls (nothing to do at p = ½: s_u = 0, u₁ = ũ₁) …
  if (scale_sample_ > 0.0 && enforce(system, scale_sample_, delassus_sample_, state.a, state.u)) {
    add_last(system, state);
    correct_velocity(state);
  }
  // … then the next step's force point u_p, by further multipliers >= 0 that push the sample
  // further off the walls.
  const double half_first2 = 0.5 * first * first;
  for (Eigen::Index i = 0; i < n; ++i) {
    u_next_[i] = state.u[i] + first * state.v[i] + half_first2 * state.a[i];
  }
  if (enforce(system, scale_next_, delassus_next_, state.a, u_next_)) {
    add_last(system, state);
    apply_last(system, scale_sample_, state.u);
    correct_velocity(state);
  }
  state.t += dt;
  if (system.has_constraint_list()) {
    return state.multipliers.size() > 0 && state.multipliers.maxCoeff() > 0.0;
  }
  return state.lambda > 0.0 || state.far_lambda > 0.0;
}

}  // namespace impactid

#include "core/noh_bathe.hpp"

#include <cmath>
#include <limits>

#include "core/constraint_set.hpp"
#include "core/contact_lcp.hpp"
#include "core/stable_step.hpp"
#include "core/two_wall_contact.hpp"

namespace impactid {

bool NohBatheExplicit::initialize(const SecondOrderSystem& system,
                                  const NohBatheCoefficients& coefficients, double dt,
                                  State& start) {
  c_ = coefficients;
  dt_ = dt;
  const double p = c_.p;
  scale_start_ = 0.5 * (p * dt) * (p * dt);
  scale_first_ = 0.5 * (1.0 - p) * dt * dt;
  scale_second_ = dt * dt * p * ((1.0 - p) * c_.q2 + 0.5 * p);

  // Ω_crit(p) over the Gershgorin bound on ω_max (+inf, nothing certified, for a mass that is not
  // diagonal).
  const double bound = highest_frequency_squared_bound(system);
  const double omega_crit = noh_bathe_critical_omega(p);
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
  delassus_second_ = scale_second_ * delassus_start_;
  delassus_start_ *= scale_start_;
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  violation_.resize(m);
  forces_.resize(m);
  scaled_forces_.resize(m);
  scratch_.resize(n);

  sub_ = start;  // sizes the sub-step's state
  u_next_ = start.u + (p * dt) * start.v + scale_start_ * start.a;
  enforce(system, scale_start_, delassus_start_, start.a, u_next_, start);
  return true;
}

void NohBatheExplicit::solve_acceleration(const SecondOrderSystem& system, const Eigen::VectorXd& u,
                                          const Eigen::VectorXd& v_predicted, Eigen::VectorXd& a) {
  a.setZero();
  system.stiffness.multiply_add(-1.0, u, a);
  if (system.has_damping()) system.damping.multiply_add(-1.0, v_predicted, a);
  mass_.solve_in_place(a);
}

bool NohBatheExplicit::enforce(const SecondOrderSystem& system, double scale,
                               const Eigen::MatrixXd& delassus, Eigen::VectorXd& a,
                               Eigen::VectorXd& next, State& at) {
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
    apply_constraint_forces(constraint_influence_, constraint_rows_, forces_, a);
    scaled_forces_ = scale * forces_;
    apply_constraint_forces(constraint_influence_, constraint_rows_, scaled_forces_, next);
    snap_walls(system.constraints, forces_, next);
    at.multipliers = forces_;  // the same size: no allocation
    at.lambda = 0.0;           // the list's are in multipliers
    return forces_.size() > 0 && forces_.maxCoeff() > 0.0;
  }
  const Eigen::Index contact = system.contact_dof;
  if (system.has_far_contact()) {
    const Eigen::Index far = system.far_contact_dof;
    const TwoWallForces forces =
        solve_two_wall_contact(next[contact] - system.gap, -system.far_gap - next[far],
                               scale * contact_influence_[contact], scale * far_influence_[far],
                               scale * far_influence_[contact], scale * contact_influence_[far]);
    if (forces.main > 0.0) {
      a -= forces.main * contact_influence_;
      next -= (scale * forces.main) * contact_influence_;
    }
    if (forces.far > 0.0) {
      a += forces.far * far_influence_;
      next += (scale * forces.far) * far_influence_;
    }
    if (forces.main > 0.0) next[contact] = system.gap;  // exact, not a few ulps off
    if (forces.far > 0.0) next[far] = -system.far_gap;
    at.lambda = forces.main;
    at.far_lambda = forces.far;
    return forces.main > 0.0 || forces.far > 0.0;
  }
  at.lambda = 0.0;
  if (!system.has_contact() || !(next[contact] > system.gap)) return false;
  const double lambda = (next[contact] - system.gap) / (scale * contact_influence_[contact]);
  a -= lambda * contact_influence_;
  next -= (scale * lambda) * contact_influence_;
  next[contact] = system.gap;
  at.lambda = lambda;
  return true;
}

bool NohBatheExplicit::step(const SecondOrderSystem& system, State& state) {
  const Eigen::Index n = system.size();
  const double p = c_.p, dt = dt_;
  const double first = p * dt, second = (1.0 - p) * dt;

  // Sub-step 1: equilibrium at t + pΔt, at the displacement the previous sub-step fixed.
  sub_.u = u_next_;
  for (Eigen::Index i = 0; i < n; ++i) scratch_[i] = state.v[i] + first * state.a[i];
  solve_acceleration(system, sub_.u, scratch_, sub_.a);
  // The contact-free u₁ = u_p + (1−p)Δt·(v₀ + pΔt/2·a₀) + c₁·a_p.
  for (Eigen::Index i = 0; i < n; ++i) {
    u_next_[i] =
        sub_.u[i] + second * (state.v[i] + 0.5 * first * state.a[i]) + scale_first_ * sub_.a[i];
  }
  enforce(system, scale_first_, delassus_first_, sub_.a, u_next_, sub_);
  for (Eigen::Index i = 0; i < n; ++i) {
    sub_.v[i] = state.v[i] + 0.5 * first * (state.a[i] + sub_.a[i]);
  }
  sub_.t = state.t + first;

  // Sub-step 2: equilibrium at t + Δt. state.v first takes the part of v₁ without a₁ (a₀ is
  // still in state.a), and scratch_ the velocity predictor v_p + (1−p)Δt·a_p.
  state.u = u_next_;
  const double w0 = second * c_.q0, wp = second * (0.5 + c_.q1), w1 = second * c_.q2;
  for (Eigen::Index i = 0; i < n; ++i) {
    scratch_[i] = sub_.v[i] + second * sub_.a[i];
    state.v[i] = sub_.v[i] + w0 * state.a[i] + wp * sub_.a[i];
  }
  solve_acceleration(system, state.u, scratch_, state.a);
  // The contact-free u_{1+p} = u₁ + pΔt·(v₁ − w1·a₁) + c₂·a₁.
  for (Eigen::Index i = 0; i < n; ++i) {
    u_next_[i] = state.u[i] + first * state.v[i] + scale_second_ * state.a[i];
  }
  const bool pushing = enforce(system, scale_second_, delassus_second_, state.a, u_next_, state);
  for (Eigen::Index i = 0; i < n; ++i) state.v[i] += w1 * state.a[i];
  state.t += dt;
  return pushing;
}

}  // namespace impactid

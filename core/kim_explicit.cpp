#include "core/kim_explicit.hpp"

namespace impactid {

bool KimExplicit::initialize(const SecondOrderSystem& system,
                             const KimExplicitCoefficients& coefficients, double dt, State& start,
                             const ContactPenalties& contact) {
  c_ = coefficients;
  dt_ = dt;
  const double p = c_.p, dt2 = dt * dt;
  if (!contact_.initialize(system, contact, kim_explicit_critical_omega(p), dt)) return false;
  const double scale_sample = c_.cu * c_.d1 * dt2;
  start_ = contact_.problem(0.5 * (p * dt) * (p * dt));
  first_ = contact_.problem(c_.up * dt2);
  sample_ = contact_.problem(scale_sample);
  next_ = contact_.problem(scale_sample + p * c_.cv * c_.d1 * dt2 + 0.5 * p * p * dt2);
  const Eigen::Index n = system.size();
  a0_.resize(n);
  u_predicted_.resize(n);
  v_predicted_.resize(n);

  if (system.has_constraint_list()) {
    start.multipliers.resize(static_cast<Eigen::Index>(system.constraints.size()));
  }
  sub_ = start;  // sizes the stage's state
  u_next_ = start.u + (p * dt) * start.v + start_.scale * start.a;
  clear_multipliers(start);
  if (contact_.enforce(system, start_, start.a, u_next_, start.u)) {
    contact_.add_last(system, start);
  }
  return true;
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
  contact_.solve_acceleration(system, sub_.u, sub_.v, sub_.a);
  // The contact-free ũ₁ = u₀ + Δt·v₀ + Δt²·u0·a₀ + s₁·a_p; λ_p puts it on the walls.
  const double u0 = c_.u0 * dt * dt;
  for (Eigen::Index i = 0; i < n; ++i) {
    u_predicted_[i] = state.u[i] + dt * state.v[i] + u0 * a0_[i] + first_.scale * sub_.a[i];
  }
  clear_multipliers(sub_);
  if (contact_.enforce(system, first_, sub_.a, u_predicted_, sub_.u)) {
    contact_.add_last(system, sub_);
  }
  sub_.t = state.t + first;

  // Stage 2: equilibrium at t + Δt, at ũ₁ with the velocity predictor ṽ₁.
  const double v0 = c_.v0 * dt, vp = c_.vp * dt;
  for (Eigen::Index i = 0; i < n; ++i) {
    v_predicted_[i] = state.v[i] + v0 * a0_[i] + vp * sub_.a[i];
  }
  contact_.solve_acceleration(system, u_predicted_, v_predicted_, state.a);
  correct(state);
  clear_multipliers(state);
  if (contact_.law().law == ContactLaw::penalty) {
    // The explicit spring force of the equilibrium at ũ₁ (the header): it moves u₁ by s_u per
    // unit of a₁ and the velocity through the divided difference; nothing is solved for the
    // next force point.
    if (contact_.enforce(system, sample_, state.a, state.u, u_predicted_)) {
      contact_.add_last(system, state);
      correct_velocity(state);
    }
  } else {
    // λ₁: first the sample u₁ on the walls (nothing to do at p = ½: s_u = 0, u₁ = ũ₁) …
    if (sample_.scale > 0.0 && contact_.enforce(system, sample_, state.a, state.u, state.u)) {
      contact_.add_last(system, state);
      correct_velocity(state);
    }
  }
  // … then the next step's force point u_p, by further multipliers >= 0 that push the sample
  // further off the walls (not for the penalty, whose force is that of ũ₁ alone).
  const double half_first2 = 0.5 * first * first;
  for (Eigen::Index i = 0; i < n; ++i) {
    u_next_[i] = state.u[i] + first * state.v[i] + half_first2 * state.a[i];
  }
  if (contact_.law().law != ContactLaw::penalty &&
      contact_.enforce(system, next_, state.a, u_next_, u_next_)) {
    contact_.add_last(system, state);
    contact_.apply_last(system, sample_.scale, state.u);
    correct_velocity(state);
  }
  state.t += dt;
  if (system.has_constraint_list()) {
    return state.multipliers.size() > 0 && state.multipliers.maxCoeff() > 0.0;
  }
  return state.lambda > 0.0 || state.far_lambda > 0.0;
}

}  // namespace impactid

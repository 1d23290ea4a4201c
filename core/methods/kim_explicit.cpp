#include "core/methods/kim_explicit.hpp"

namespace impactid {
namespace {

// Whether the multipliers are a constraint list's (a sparse model's always are).
bool listed(const SecondOrderSystem& system) {
  return system.has_constraint_list();
}
bool listed(const SparseSystem&) {
  return true;
}

}  // namespace

template <class StageContact, SemiDiscreteSystem System>
bool KimScheme<StageContact, System>::initialize(const System& system,
                                                 const KimExplicitCoefficients& coefficients,
                                                 double dt, State& start,
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

  if (listed(system)) {
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

template <class StageContact, SemiDiscreteSystem System>
void KimScheme<StageContact, System>::clear_multipliers(State& at) {
  at.lambda = 0.0;
  at.far_lambda = 0.0;
  at.multipliers.setZero();
}

template <class StageContact, SemiDiscreteSystem System>
double KimScheme<StageContact, System>::divided_difference(Eigen::Index i,
                                                           const State& state) const {
  return c_.d0 * a0_[i] + c_.dp * sub_.a[i] + c_.d1 * state.a[i];
}

template <class StageContact, SemiDiscreteSystem System>
void KimScheme<StageContact, System>::correct(State& state) const {
  const Eigen::Index n = state.u.size();
  const double du = c_.cu * dt_ * dt_, dv = c_.cv * dt_;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = divided_difference(i, state);
    state.u[i] = u_predicted_[i] + du * d;
    state.v[i] = v_predicted_[i] + dv * d;
  }
}

template <class StageContact, SemiDiscreteSystem System>
void KimScheme<StageContact, System>::correct_velocity(State& state) const {
  const Eigen::Index n = state.v.size();
  const double dv = c_.cv * dt_;
  for (Eigen::Index i = 0; i < n; ++i)
    state.v[i] = v_predicted_[i] + dv * divided_difference(i, state);
}

template <class StageContact, SemiDiscreteSystem System>
bool KimScheme<StageContact, System>::step(const System& system, State& state) {
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
  if (contact_.law().explicit_force()) {
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
  // further off the walls (not for the penalty, whose force is that of ũ₁ alone). That holds
  // constraint by constraint: with a lumped mass a force moves only its own contact's DOFs, but a
  // consistent M⁻¹ has entries of both signs, so with several coupled contacts (a 2D model's edge)
  // one contact's push can move a neighbouring sample node toward its wall by s_u·(M⁻¹·Gᵀ·μ) at
  // p < ½, a small fraction of the gap; none at p = ½ (s_u = 0) or with a lumped mass
  // (tests/sparse_explicit_test.cpp, SignoriniConditionsHoldAtEverySampleAndStageOfTheBlock). The
  // next force point holds exactly.
  const double half_first2 = 0.5 * first * first;
  for (Eigen::Index i = 0; i < n; ++i) {
    u_next_[i] = state.u[i] + first * state.v[i] + half_first2 * state.a[i];
  }
  if (!contact_.law().explicit_force() &&
      contact_.enforce(system, next_, state.a, u_next_, u_next_)) {
    contact_.add_last(system, state);
    contact_.apply_last(system, sample_.scale, state.u);
    correct_velocity(state);
  }
  state.t += dt;
  if (listed(system)) {
    return state.multipliers.size() > 0 && state.multipliers.maxCoeff() > 0.0;
  }
  return state.lambda > 0.0 || state.far_lambda > 0.0;
}

template class KimScheme<ExplicitStageContact, SecondOrderSystem>;
template class KimScheme<SparseExplicitStageContact, SparseSystem>;

}  // namespace impactid

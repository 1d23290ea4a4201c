#include "core/methods/noh_bathe.hpp"

namespace impactid {

template <class StageContact, SemiDiscreteSystem System>
bool NohBatheScheme<StageContact, System>::initialize(const System& system,
                                                      const NohBatheCoefficients& coefficients,
                                                      double dt, State& start,
                                                      const ContactPenalties& contact) {
  c_ = coefficients;
  dt_ = dt;
  const double p = c_.p;
  if (!contact_.initialize(system, contact, noh_bathe_critical_omega(p), dt)) return false;
  start_ = contact_.problem(0.5 * (p * dt) * (p * dt));
  first_ = contact_.problem(0.5 * (1.0 - p) * dt * dt);
  second_ = contact_.problem(dt * dt * p * ((1.0 - p) * c_.q2 + 0.5 * p));
  scratch_.resize(system.size());

  sub_ = start;  // sizes the sub-step's state
  u_next_ = start.u + (p * dt) * start.v + start_.scale * start.a;
  contact_.enforce(system, start_, start.a, u_next_, start.u);
  contact_.write_last(system, start);
  return true;
}

template <class StageContact, SemiDiscreteSystem System>
bool NohBatheScheme<StageContact, System>::step(const System& system, State& state) {
  const Eigen::Index n = system.size();
  const double p = c_.p, dt = dt_;
  const double first = p * dt, second = (1.0 - p) * dt;

  // Sub-step 1: equilibrium at t + pΔt, at the displacement the previous sub-step fixed.
  sub_.u = u_next_;
  for (Eigen::Index i = 0; i < n; ++i) scratch_[i] = state.v[i] + first * state.a[i];
  contact_.solve_acceleration(system, sub_.u, scratch_, sub_.a);
  // The contact-free u₁ = u_p + (1−p)Δt·(v₀ + pΔt/2·a₀) + c₁·a_p.
  for (Eigen::Index i = 0; i < n; ++i) {
    u_next_[i] =
        sub_.u[i] + second * (state.v[i] + 0.5 * first * state.a[i]) + first_.scale * sub_.a[i];
  }
  contact_.enforce(system, first_, sub_.a, u_next_, sub_.u);
  contact_.write_last(system, sub_);
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
  contact_.solve_acceleration(system, state.u, scratch_, state.a);
  // The contact-free u_{1+p} = u₁ + pΔt·(v₁ − w1·a₁) + c₂·a₁.
  for (Eigen::Index i = 0; i < n; ++i) {
    u_next_[i] = state.u[i] + first * state.v[i] + second_.scale * state.a[i];
  }
  const bool pushing = contact_.enforce(system, second_, state.a, u_next_, state.u);
  contact_.write_last(system, state);
  for (Eigen::Index i = 0; i < n; ++i) state.v[i] += w1 * state.a[i];
  state.t += dt;
  return pushing;
}

template class NohBatheScheme<ExplicitStageContact, SecondOrderSystem>;
template class NohBatheScheme<SparseExplicitStageContact, SparseSystem>;

}  // namespace impactid

// The composite schemes of the Bathe family (Bathe, ρ∞-Bathe; core/methods/method.hpp) stepped by
// the integrators of the single-step implicit family, two of them per run:
//   1. `first_` takes the trapezoidal sub-step from t to t + γ·Δt (step γ·Δt);
//   2. the second sub-step's predictors are formed from the states at t and t + γ·Δt,
//        v* = v₀ + Δt·(q0·a₀ + q1·a_γ),   u* = u₀ + Δt·(q0·v₀ + q1·v_γ) + q2·Δt·v*,
//      and written into the state as a start from which `second_`'s family member
//      (b0 = g0 = 0, b1 = q2², g1 = q2, α_m = α_f = 0) predicts exactly u* and v*: u = u* − Δt·v*,
//      v = v*. `second_` then solves for a₁ with u₁ = u* + q2²·Δt²·a₁, v₁ = v* + q2·Δt·a₁.
// Each sub-step is a full step of its integrator, contact included: the constraints hold (and
// the multipliers are >= 0) at t + γ·Δt and at t + Δt, each multiplier the force at the end of its
// sub-step. The sample at t + Δt reports the second's. Why at both: a sub-step that ended in
// penetration would start the second from a state the contact law forbids, and its predictors
// (which weigh v_γ and a_γ) carry the penetration's momentum into the step's end: on the paper's
// scene every run with the first sub-step unconstrained went unstable (the figures are in the git
// log). tests/bathe_composite_test.cpp, SignoriniConditionsHoldAtEverySubStepAndSample, checks
// both ends. The first sub-step is the trapezoidal rule, whose Lagrange contact chatters on its
// own (core/methods/method.hpp, NewmarkParams), so some runs still end unstable there (ρ∞ = 1,
// the trapezoidal rule twice, among them), as Newmark with δ = 0 does.
//
// Works with ImplicitIntegrator (tridiagonal systems: the rod, scenes of bodies) and
// SparseImplicitIntegrator (a user's model) alike. Per step: two solves of each integrator's
// factorised matrix (when γ = γ₀ the two effective matrices are equal, but each integrator keeps
// its own factorisation), O(n) extra vector work, no allocation once the state's sizes are set.
//
// Thread safety: one object per thread (it holds the sub-step's state).
#pragma once

#include "core/common/state.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/methods/method.hpp"
#include "core/model/semi_discrete_system.hpp"

namespace impactid {

// System: SecondOrderSystem with ImplicitIntegrator, SparseSystem with SparseImplicitIntegrator.
template <class Integrator, SemiDiscreteSystem System>
class BatheComposite {
 public:
  /// Factors both sub-steps' effective matrices. False if either is singular (or not positive
  /// definite, for the sparse integrator, whose failure() then says why).
  /// `contact`: the contact law of both sub-steps (core/contact/contact_treatment.hpp).
  bool initialize(const System& system, const CompositeCoefficients& coefficients, double dt,
                  const ContactPenalties& contact = {}) {
    c_ = coefficients;
    dt_ = dt;
    return first_.initialize(system, c_.first, c_.gamma * dt, contact) &&
           second_.initialize(system, c_.second, dt, contact);
  }

  /// Both sub-steps' augmented-Lagrangian iterations, and their steps that hit the cap.
  long contact_iterations() const {
    return first_.contact_iterations() + second_.contact_iterations();
  }
  long unconverged_contact_steps() const {
    return first_.unconverged_contact_steps() + second_.unconverged_contact_steps();
  }

  /// Advances state from t to t + Δt; its acceleration must be consistent with u and v (as for
  /// the integrators). Returns the second sub-step's contact status.
  bool step(const System& system, State& state) {
    mid_ = state;  // the vectors keep their storage once sized: no allocation after the first step
    first_.step(system, mid_);
    v_star_ = state.v + dt_ * (c_.q0 * state.a + c_.q1 * mid_.a);
    state.u += dt_ * (c_.q0 * state.v + c_.q1 * mid_.v) + ((c_.q2 - 1.0) * dt_) * v_star_;
    state.v = v_star_;
    return second_.step(system, state);
  }

  /// The state at t + γ·Δt of the last step (for tests of the sub-step's contact conditions).
  const State& substep_state() const { return mid_; }
  /// The integrator of the second sub-step (its failure() for the sparse one).
  const Integrator& second() const { return second_; }
  const Integrator& first() const { return first_; }

 private:
  CompositeCoefficients c_{};
  double dt_ = 0.0;
  Integrator first_, second_;
  State mid_;
  Eigen::VectorXd v_star_;
};

}  // namespace impactid

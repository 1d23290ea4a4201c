// Houbolt's method (Houbolt 1950, J. Aeronaut. Sci. 17(9):540–550, doi:10.2514/8.1722;
// core/methods/method.hpp, HouboltParams) stepped by integrators of the single-step implicit
// family.
//
// The step. Houbolt's formulas, solved for the new displacement and velocity,
//   u_{n+1} = u* + ½·Δt²·a_{n+1},        u* = (5u_n − 4u_{n−1} + u_{n−2})/2,
//   v_{n+1} = v* + (11/12)·Δt·a_{n+1},   v* = (19u_n − 26u_{n−1} + 7u_{n−2})/(12Δt),
// are the family member b0 = g0 = 0, b1 = ½, g1 = 11/12 (α_m = α_f = 0) started from u*, v*.
// The predictors are written into the state as a start from which that member predicts exactly
// u* and v* (u = u* − Δt·v*, v = v*), as core/methods/bathe_composite.hpp does for its second
// sub-step, and the integrator then solves M·a + C·v + K·u + Gᵀ·λ = 0 at t_{n+1}, i.e. Houbolt's
// equation (M·2/Δt² + C·11/(6Δt) + K)·u_{n+1} = … on the effective matrix M + (11/12)·Δt·C +
// ½·Δt²·K. Its contact is the integrator's: the constraints hold at t_{n+1} and the multipliers
// there are >= 0 (single wall, two walls, a constraint list, a sparse model alike), and that is the
// multiplier a sample reports. The penalty and augmented-Lagrangian laws come the same way: each
// integrator's spring acts at t_{n+1}, λ = k·max(0, g_{n+1}) (core/contact/contact_treatment.hpp).
//
// The start-up. The cubic needs u_{n−1} and u_{n−2}, which do not exist for the first two steps.
// They take the same cubic with the initial velocity and acceleration standing in for the
// missing displacements (Hermite data at t₀):
//   step 1, the cubic through u₀, v₀, a₀ and u₁: u₁ = u₀ + Δt·v₀ + Δt²(a₀/3 + a₁/6),
//           v₁ = v₀ + Δt(a₀ + a₁)/2, the linear-acceleration step (Newmark β = 1/6, γ = ½);
//   step 2, the cubic through u₀, v₀, u₁ and u₂: a₂ = (5u₂ − 16u₁ + 11u₀ + 6Δt·v₀)/(2Δt²),
//           v₂ = v₀ + 2(u₂ − 2u₁ + u₀)/Δt, the member b1 = 2/5, g1 = 4/5 from
//           u* = (16u₁ − 11u₀ − 6Δt·v₀)/5, v* = v₀ + 2(u* − 2u₁ + u₀)/Δt.
// Why these: each is exact for a cubic u(t), like Houbolt's step itself, so the start has the
// method's own local error, O(Δt⁴) in u and O(Δt³) in v (tests/houbolt_test.cpp,
// StartUpKeepsTheLocalErrorOfTheCubic, measures both orders after one, two and three steps). The
// alternatives lose an order: backward differences of lower order in the same family (backward
// Euler, then BDF2) would make errors O(Δt²) and O(Δt³) in u, and past displacements from a Taylor
// expansion, u_{−k} = u₀ − kΔt·v₀ + (kΔt)²/2·a₀, errors O(Δt³), which a method with a double root
// at 1 carries to every later step. Each start step is a full step of its integrator, contact
// included. A run that starts in rigid free flight (every built-in scene, core/run/simulation.hpp)
// is reproduced exactly by all three steps, so where the start falls does not matter there. The
// price: three factorised effective matrices per run (M + ½Δt·C + Δt²/6·K, M + (4/5)Δt·C +
// (2/5)Δt²·K, and Houbolt's), two of them used twice.
//
// Houbolt is a three-step method: its state is (u_n, u_{n−1}, u_{n−2}), and the object keeps the
// two past displacements; restarting from a State (initialize()) restarts the start-up.
//
// Works with ImplicitIntegrator (tridiagonal systems: the rod, scenes of bodies) and
// SparseImplicitIntegrator (a user's model) alike. Per step: one solve of the integrator's
// factorised matrix, O(n) extra vector work, no allocation once the state's sizes are set.
//
// Thread safety: one object per thread (it holds the past displacements).
#pragma once

#include "core/common/state.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/methods/method.hpp"
#include "core/model/semi_discrete_system.hpp"

namespace impactid {

// System: SecondOrderSystem with ImplicitIntegrator, SparseSystem with SparseImplicitIntegrator.
template <class Integrator, SemiDiscreteSystem System>
class Houbolt {
 public:
  /// Factors the three effective matrices and starts a new run (the next step is step 1). False
  /// if one is singular (or not positive definite, for the sparse integrator, whose failure()
  /// then says why).
  /// `contact`: the contact law of all three (core/contact/contact_treatment.hpp).
  bool initialize(const System& system, double dt, const ContactPenalties& contact = {}) {
    const HouboltCoefficients c = houbolt_coefficients();
    dt_ = dt;
    taken_ = 0;
    return first_.initialize(system, c.first, dt, contact) &&
           second_.initialize(system, c.second, dt, contact) &&
           steady_.initialize(system, c.steady, dt, contact);
  }

  /// The augmented-Lagrangian iterations of the three integrators, and their steps at the cap.
  long contact_iterations() const {
    return first_.contact_iterations() + second_.contact_iterations() +
           steady_.contact_iterations();
  }
  long unconverged_contact_steps() const {
    return first_.unconverged_contact_steps() + second_.unconverged_contact_steps() +
           steady_.unconverged_contact_steps();
  }

  /// Advances state from t to t + Δt; the first step's acceleration must be consistent with u
  /// and v (as for the integrators). Returns the step's contact status (a constraint active at
  /// t + Δt).
  bool step(const System& system, State& state) {
    const Eigen::Index n = state.u.size();
    const double dt = dt_;
    if (taken_ == 0) {  // the linear-acceleration step from u₀, v₀, a₀
      taken_ = 1;
      back1_ = state.u;  // u₀
      start_velocity_ = state.v;
      return first_.step(system, state);
    }
    if (taken_ == 1) {  // the cubic through u₀, v₀, u₁, u₂
      taken_ = 2;
      back2_.swap(back1_);  // u₀
      back1_ = state.u;     // u₁
      for (Eigen::Index i = 0; i < n; ++i) {
        const double u0 = back2_[i], u1 = back1_[i], v0 = start_velocity_[i];
        const double u_star = (16.0 * u1 - 11.0 * u0 - 6.0 * dt * v0) / 5.0;
        const double v_star = v0 + 2.0 * (u_star - 2.0 * u1 + u0) / dt;
        state.u[i] = u_star - dt * v_star;
        state.v[i] = v_star;
      }
      return second_.step(system, state);
    }
    now_ = state.u;  // u_n, before the predictors overwrite it
    for (Eigen::Index i = 0; i < n; ++i) {
      const double un = now_[i], u1 = back1_[i], u2 = back2_[i];
      const double u_star = 0.5 * (5.0 * un - 4.0 * u1 + u2);
      const double v_star = (19.0 * un - 26.0 * u1 + 7.0 * u2) / (12.0 * dt);
      state.u[i] = u_star - dt * v_star;
      state.v[i] = v_star;
    }
    back2_.swap(back1_);  // u_{n−1} becomes u_{n−2}
    back1_.swap(now_);    // u_n becomes u_{n−1}; now_ is scratch again
    return steady_.step(system, state);
  }

  /// How many steps since initialize() (the start-up is steps 1 and 2), capped at 2.
  int steps_taken() const { return taken_; }
  /// The integrators of the start's two steps and of Houbolt's (their failure() for the sparse
  /// one).
  const Integrator& first() const { return first_; }
  const Integrator& second() const { return second_; }
  const Integrator& steady() const { return steady_; }

 private:
  double dt_ = 0.0;
  int taken_ = 0;
  Integrator first_, second_, steady_;
  Eigen::VectorXd back1_, back2_, now_;  // u_{n−1}, u_{n−2}, scratch
  Eigen::VectorXd start_velocity_;       // v₀, for step 2
};

}  // namespace impactid

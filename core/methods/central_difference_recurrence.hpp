// Central difference's recurrence (core/methods/central_difference.hpp), written once for every
// system (core/model/semi_discrete_system.hpp): the tridiagonal stepper (CentralDifference) and
// the sparse one (SparseCentralDifference, core/methods/sparse_integrators.hpp) both step with it,
// and differ only in how they enforce the contact between predict() and finish().
//
//   start():    u₋ = u₀ − Δt·v₀ + ½Δt²·a₀ (Taylor, second order);
//   predict():  (M/Δt² + C/(2Δt))·u₊ = M·(2u − u₋)/Δt² − K·u + C·u₋/(2Δt) for the central velocity,
//               M/Δt²·u₊ = M·(2u − u₋)/Δt² − K·u − C·(u − u₋)/Δt for the backward one, solved with
//               the caller's factorisation of the left-hand matrix; a system's constant load f
//               (core/model/constant_load.hpp) is added to either right-hand side;
//   finish():   the state at t (u, the variant's velocity, a = (u₊ − 2u + u₋)/Δt², t), then the
//               recurrence moves on to t + Δt;
//   energy():   the method's own energy at t + Δt/2 (central_difference_energy).
//
// No allocation once start() has sized the vectors. Thread safety: one object per thread.
#pragma once

#include <Eigen/Core>
#include <type_traits>

#include "core/common/state.hpp"
#include "core/methods/method.hpp"
#include "core/model/semi_discrete_system.hpp"

namespace impactid {

/// Central difference's own energy at t + Δt/2 from u_t and u_{t+Δt}, with
/// w = (u_{t+Δt} − u_t)/Δt and m = (u_t + u_{t+Δt})/2, given the quadratic forms wᵀMw, wᵀKw and
/// mᵀKm:
///   E = |½·wᵀ(M − Δt²/4·K)·w| + ½·mᵀK·m.
/// Without the absolute value this is the energy the undamped, contact-free scheme conserves
/// exactly (it equals ½·wᵀMw + ½·u_tᵀK·u_{t+Δt}); the plain ½vᵀMv + ½uᵀKu of the reported central
/// velocity is not conserved, and misleads at the "magic" time step: with a lumped mass at Courant
/// 1 the rod's highest mode has Ω = ωΔt = 2 exactly, its repeated eigenvalue −1 makes it grow
/// linearly, u_k = (A + B·k)·(−1)^k, once contact release excites it, and the plain energy grows
/// quadratically while the nodal displacements stay d'Alembert's
/// (tests/central_difference_test.cpp, MagicTimeStepIsOkByItsOwnEnergy). That mode lies in the null
/// space of M − Δt²/4·K and its midpoint m is constant, so E stays bounded. Above the limit (Ω > 2)
/// M − Δt²/4·K is indefinite and the conserved form could stay constant while both parts grow
/// geometrically with opposite signs: the absolute value makes each part count, so an unstable mode
/// still raises E.
double central_difference_energy(double mass_w, double stiffness_w, double stiffness_m, double dt);

struct CentralDifferenceRecurrence {
  CdmVelocity velocity = CdmVelocity::central;
  double dt = 0.0;
  double t = 0.0;                              ///< the time of u
  Eigen::VectorXd u_previous, u, u_next;       ///< u₋, u at t, u₊
  Eigen::VectorXd scratch;
  /// On a sparse model without damping whose M stores its diagonal only and whose K is exactly
  /// symmetric (stores_diagonal_only, is_exactly_symmetric: core/model/sparse_system.hpp), the
  /// caller may set this: predict() then forms M·s − K·u in one pass over the rows, gathering K's
  /// column i for row i, the same products in the same order as the two column-by-column
  /// products, so the same bits (the batched model kernel's predict_fused does the same).
  bool one_pass = false;

  /// From `initial` at t₀ (a₀ consistent); sizes the vectors.
  void start(CdmVelocity variant, double step, const State& initial) {
    velocity = variant;
    dt = step;
    t = initial.t;
    u = initial.u;
    // Taylor start, second order: u₋ = u₀ − Δt·v₀ + ½Δt²·a₀. For the rod (a₀ = 0) this is the
    // convention u₋₁ = u₀ − Δt·v0; without the a₀ term a displaced start is only first order.
    u_previous = initial.u - dt * initial.v + (0.5 * dt * dt) * initial.a;
    u_next.resize(u.size());
    scratch.resize(u.size());
  }

  /// The contact-free u₊ (the header), solved with `lhs`, the factorised left-hand matrix.
  template <SemiDiscreteSystem System>
  void predict(const System& system, const typename System::Factorization& lhs) {
    const Eigen::Index n = system.size();
    const double inv_dt2 = 1.0 / (dt * dt);
    if constexpr (std::is_same_v<System, SparseSystem>) {
      if (one_pass) {
        const double* mass = system.mass.valuePtr();
        const double* values = system.stiffness.valuePtr();
        const int* rows = system.stiffness.innerIndexPtr();
        const int* starts = system.stiffness.outerIndexPtr();
        for (Eigen::Index i = 0; i < n; ++i) {
          const double s = (2.0 * u[i] - u_previous[i]) * inv_dt2;
          double sum = s != 0.0 ? 0.0 + mass[i] * s : 0.0;  // multiply(): 0 + m·s, skipped at 0
          for (int e = starts[i]; e < starts[i + 1]; ++e) {
            const double sx = -1.0 * u[rows[e]];
            if (sx != 0.0) sum += values[e] * sx;
          }
          u_next[i] = sum;
        }
        if (system.load.active()) u_next += system.load.force;
        lhs.solve_in_place(u_next);
        return;
      }
    }
    // rhs = M·(2u − u₋)/Δt² − K·u − (damping term of the variant)
    for (Eigen::Index i = 0; i < n; ++i) scratch[i] = (2.0 * u[i] - u_previous[i]) * inv_dt2;
    multiply(system.mass, scratch, u_next);
    multiply_add(system.stiffness, -1.0, u, u_next);
    if (system.has_damping()) {
      if (velocity == CdmVelocity::central) {
        multiply_add(system.damping, 0.5 / dt, u_previous, u_next);
      } else {
        for (Eigen::Index i = 0; i < n; ++i) scratch[i] = (u[i] - u_previous[i]) / dt;
        multiply_add(system.damping, -1.0, scratch, u_next);
      }
    }
    if (system.load.active()) u_next += system.load.force;
    lhs.solve_in_place(u_next);
  }

  /// Fills `at_t` with u, the variant's velocity, the acceleration and the time of the current
  /// sample (its multipliers are the caller's), then moves on to t + Δt.
  void finish(State& at_t) {
    const double inv_dt2 = 1.0 / (dt * dt);
    at_t.u = u;
    if (velocity == CdmVelocity::central) {
      at_t.v = (u_next - u_previous) / (2.0 * dt);
    } else {
      at_t.v = (u - u_previous) / dt;
    }
    at_t.a = (u_next - 2.0 * u + u_previous) * inv_dt2;
    at_t.t = t;
    u_previous.swap(u);
    u.swap(u_next);
    t += dt;
  }

  /// The method's own energy at t + Δt/2 after finish(): u_previous = u_t, u = u_{t+Δt}; scratch
  /// and u_next are free until the next predict(). With a load f, its potential at the midpoint m
  /// is added: the scheme M·(u₊ − 2u + u₋)/Δt² + K·u = f conserves E − fᵀ·m exactly.
  template <SemiDiscreteSystem System>
  double energy(const System& system) {
    scratch = (u - u_previous) / dt;
    u_next = 0.5 * (u + u_previous);
    const double e = central_difference_energy(quadratic_form(system.mass, scratch),
                                               quadratic_form(system.stiffness, scratch),
                                               quadratic_form(system.stiffness, u_next), dt);
    return system.load.active() ? e + system.load.potential(u_next) : e;
  }
};

}  // namespace impactid

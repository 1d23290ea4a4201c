// KR-α's update formulas (core/methods/kr_alpha.hpp: the model-based matrices applied through the
// factorised M, D and E, the velocity v̂ lagging the sample's by γΔt, the half-step energy),
// written once for both systems: the tridiagonal one (core/methods/kr_alpha.hpp, Matrix =
// Tridiagonal) and a user's sparse model (core/methods/sparse_kr_alpha.hpp, Matrix = SparseMatrix).
// They differ only in their matrix products, the free functions multiply, multiply_add and
// quadratic_form of each matrix type (core/model/sparse_system.hpp, core/algebra/tridiagonal.hpp),
// chosen at compile time; and in their contact, which the steppers pass to step() as `enforce`.
//
// No allocation in step() or energy() once initialize() has sized the vectors.
//
// Thread safety: one object per thread (scratch vectors).
#pragma once

#include <Eigen/Core>

#include "core/algebra/tridiagonal.hpp"
#include "core/common/state.hpp"
#include "core/methods/method.hpp"
#include "core/model/semi_discrete_system.hpp"

namespace impactid {

template <class Matrix, class Factorization>
struct KrAlphaRecurrence {
  KrAlphaCoefficients c{};
  double dt = 0.0;
  double scale = 0.0;        ///< s = Δt²(½ + γ): the next displacement's factor on w = α1·a
  Matrix d_matrix;           ///< D = M + γΔt·C + βΔt²·K
  Factorization mass, d, e;  ///< d: the start's only (α1·a₀); a step solves with E and M
  Eigen::VectorXd w;       ///< α1·a of the current sample (Δt·w is the next velocity increment)
  Eigen::VectorXd v_hat;   ///< the method's velocity v̂, which lags the sample's by γΔt
  Eigen::VectorXd u_next;  ///< the next sample's displacement, fixed by the last equilibrium
  Eigen::VectorXd r, y;    ///< scratch

  /// Sizes the vectors for n DOFs (set-up).
  void resize(Eigen::Index n) {
    r.resize(n);
    y.resize(n);
    w.resize(n);
  }

  /// The start (core/methods/kr_alpha.hpp): u₁ = u₀ + Δt·v̂₀ + s·α1·a₀ with v̂₀ = v₀ − γΔt·α1·a₀ is
  /// u₀ + Δt·v₀ + Δt²/2·α1·a₀; `enforce(next)` applies the start's contact to `start` and u_next
  /// (and to w, the response of α1·a, and to start.a).
  template <SemiDiscreteSystem System, class Enforce>
  void start(const System& system, State& start, Enforce&& enforce) {
    multiply(system.mass, start.a, w);
    d.solve_in_place(w);  // α1·a₀
    u_next = start.u + dt * start.v + (0.5 * dt * dt) * w;
    enforce(u_next);
    v_hat = start.v - (c.gamma * dt) * w;
  }

  /// Advances state from t to t + Δt; `enforce(next)` applies the contact of the equilibrium at
  /// t + Δt to the contact-free next displacement and to w (the acceleration follows from w) and
  /// returns whether a constraint pushes, which step() returns.
  template <SemiDiscreteSystem System, class Enforce>
  bool step(const System& system, State& state, Enforce&& enforce) {
    const Eigen::Index n = system.size();
    const double af = c.alpha_f;
    const bool damped = system.has_damping();

    // r = f − K·u_{1−α_f} − C·v_{1−α_f} (f: the system's load, if any): the α_f parts at t
    // first, while the state still holds them.
    if (system.load.active()) {
      r = system.load.force;  // the same size: no allocation
    } else {
      r.setZero();
    }
    multiply_add(system.stiffness, -af, state.u, r);
    if (damped) multiply_add(system.damping, -af, v_hat, r);
    // The explicit u₁ (fixed, with its contact, by the last equilibrium) and v̂₁ = v̂₀ + Δt·α1·a₀.
    state.u = u_next;
    for (Eigen::Index i = 0; i < n; ++i) v_hat[i] += dt * w[i];
    multiply_add(system.stiffness, -(1.0 - af), state.u, r);
    if (damped) multiply_add(system.damping, -(1.0 - af), v_hat, r);

    // α1·a₁ = α1·a₀ + E⁻¹·(r − D·α1·a₀): the header of core/methods/kr_alpha.hpp derives it from
    // a₁ = a₀ + E⁻¹·D·(M⁻¹·r − a₀), with one solve instead of three.
    multiply(d_matrix, w, y);
    for (Eigen::Index i = 0; i < n; ++i) y[i] = r[i] - y[i];
    e.solve_in_place(y);
    for (Eigen::Index i = 0; i < n; ++i) w[i] += y[i];

    // The contact-free u₂ = u₁ + Δt·v₁ + Δt²(½ + γ)·α1·a₁.
    for (Eigen::Index i = 0; i < n; ++i) u_next[i] = state.u[i] + dt * v_hat[i] + scale * w[i];
    const bool pushing = enforce(u_next);
    // The acceleration a₁ = M⁻¹·D·α1·a₁: reported (State::a); no step reads it.
    multiply(d_matrix, w, state.a);
    mass.solve_in_place(state.a);
    // The sample's velocity: v̂ lags u by γΔt (core/methods/kr_alpha.hpp).
    const double lead = c.gamma * dt;
    for (Eigen::Index i = 0; i < n; ++i) state.v[i] = v_hat[i] + lead * w[i];
    state.t += dt;
    return pushing;
  }

  /// KrAlphaExplicit::energy's half-step energy ½·wᵀM·w + ½·mᵀK·m, w = (u_next − u)/Δt,
  /// m = (u + u_next)/2 (and a load's potential at m), after step() returned `state`. Uses the
  /// scratch vectors.
  template <SemiDiscreteSystem System>
  double energy(const System& system, const State& state) {
    const Eigen::Index n = system.size();
    for (Eigen::Index i = 0; i < n; ++i) {
      r[i] = (u_next[i] - state.u[i]) / dt;
      y[i] = 0.5 * (state.u[i] + u_next[i]);
    }
    const double e =
        0.5 * quadratic_form(system.mass, r) + 0.5 * quadratic_form(system.stiffness, y);
    return system.load.active() ? e + system.load.potential(y) : e;
  }
};

}  // namespace impactid

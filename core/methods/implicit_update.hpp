// The update formulas of the single-step implicit family (ImplicitCoefficients,
// core/methods/method.hpp), written once for every system (core/model/semi_discrete_system.hpp):
// the tridiagonal integrator (core/methods/implicit_integrator.hpp) and the sparse one
// (core/methods/sparse_integrators.hpp) both step with them, and differ only in how they solve
// with the effective matrix and enforce the contact between predict() and update().
//
//   predict():  u* = u + Δt·v + b0·Δt²·a,  v* = v + g0·Δt·a,
//               u and v overwritten by the α_f-weighted arguments (1−α_f)·u* + α_f·u and
//               (1−α_f)·v* + α_f·v, formed as u* − α_f·(u* − u) (one multiply fewer, and exactly
//               u* for Newmark, α_f = 0), then rhs = −K·u_α − C·v_α − α_m·M·a (+ f, the system's
//               constant load when it has one: core/model/constant_load.hpp; its α-weighting is
//               f itself);
//   update():   a = rhs (the solved acceleration), u = u* + b1·Δt²·a, v = v* + g1·Δt·a.
// A multiply whose product is only added is fused with the add (std::fma, correctly rounded: the
// same bits on every machine); the batched kernel (core/batch/rod_kernel.cpp) repeats exactly
// these operations, so they must not change (tests/batched_simulation_test.cpp holds them).
//
// No allocation once resize() has sized the vectors. Thread safety: one object per thread.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "core/common/state.hpp"
#include "core/methods/method.hpp"
#include "core/model/semi_discrete_system.hpp"

namespace impactid {

struct ImplicitUpdate {
  Eigen::VectorXd u_predicted, v_predicted;  ///< u*, v*
  Eigen::VectorXd rhs;  ///< the right-hand side, then (solved by the caller) the acceleration

  void resize(Eigen::Index n) {
    u_predicted.resize(n);
    v_predicted.resize(n);
    rhs.resize(n);
  }

  /// The predictors, the α_f-weighted arguments written over s.u and s.v (their old values are
  /// not needed again), and rhs without the contact forces.
  template <SemiDiscreteSystem System>
  void predict(const System& system, const ImplicitCoefficients& c, double dt, State& s) {
    const Eigen::Index n = system.size();
    const double dt2 = dt * dt;
    const double af = c.alpha_f;
    const double dt2_b0 = dt2 * c.b0, dt_g0 = dt * c.g0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double du = std::fma(dt, s.v[i], dt2_b0 * s.a[i]);
      u_predicted[i] = s.u[i] + du;
      v_predicted[i] = std::fma(dt_g0, s.a[i], s.v[i]);
      s.u[i] = std::fma(-af, du, u_predicted[i]);
      s.v[i] = std::fma(-af, dt_g0 * s.a[i], v_predicted[i]);
    }
    multiply(system.stiffness, s.u, rhs);
    rhs = -rhs;
    if (system.has_damping()) multiply_add(system.damping, -1.0, s.v, rhs);
    if (c.alpha_m != 0.0) multiply_add(system.mass, -c.alpha_m, s.a, rhs);
    if (system.load.active()) rhs += system.load.force;
  }

  /// a, u and v of the step's end from the solved acceleration in rhs, every dof.
  void update(const ImplicitCoefficients& c, double dt, State& s) const {
    const Eigen::Index n = s.a.size();
    const double dt2 = dt * dt;
    const double b1_dt2 = c.b1 * dt2, g1_dt = c.g1 * dt;
    for (Eigen::Index i = 0; i < n; ++i) {
      s.a[i] = rhs[i];
      s.u[i] = std::fma(b1_dt2, rhs[i], u_predicted[i]);
      s.v[i] = std::fma(g1_dt, rhs[i], v_predicted[i]);
    }
  }
};

}  // namespace impactid

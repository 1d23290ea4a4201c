// One integrator for every implicit method here (backward Euler, Newmark, HHT-α,
// generalized-α): the one-step family of ImplicitCoefficients, solved in acceleration form
//   [(1−α_m)·M + (1−α_f)·(g1·Δt·C + b1·Δt²·K)]·a₁ = rhs,
// with the contact of eqs 16–17 as a one-unknown complementarity problem:
//   1. predict a₁* without a new contact force;
//   2. if the contact dof would penetrate (u_c > gap), solve for the λ₁ > 0 that puts it on the
//      wall, a₁ = a₁* − w·λ₁·A⁻¹·e_c; otherwise λ₁ = 0 (a tensile λ is released).
// The effective matrix A is constant, so it is factored once in initialize() together with the
// contact influence vector A⁻¹·e_c, and every step is O(n) with no allocation.
//
// Thread safety: one object per thread (it holds scratch vectors).
#pragma once

#include "core/method.hpp"
#include "core/second_order_system.hpp"
#include "core/state.hpp"
#include "core/tridiagonal.hpp"

namespace impactid {

class ImplicitIntegrator {
 public:
  /// Builds and factors the effective matrix. Returns false if it is singular (e.g. a
  /// non-positive mass), in which case step() must not be called.
  bool initialize(const SecondOrderSystem& system, const ImplicitCoefficients& coefficients,
                  double dt);

  /// Advances state from t to t + Δt. The state's acceleration must be consistent with its
  /// displacement and velocity (see consistent_acceleration). Returns true if the contact is
  /// active at t + Δt (λ > 0); the contact dof is then exactly on the wall.
  bool step(const SecondOrderSystem& system, State& state);

 private:
  ImplicitCoefficients c_{};
  double dt_ = 0.0;
  TridiagonalFactorization factorization_;
  Eigen::VectorXd contact_influence_;  // A⁻¹·e_c
  Eigen::VectorXd u_predicted_, v_predicted_, rhs_;
};

/// a solving M·a = −K·u − C·v − G^T·λ: the acceleration consistent with the equation of motion.
Eigen::VectorXd consistent_acceleration(const SecondOrderSystem& system, const State& state);

}  // namespace impactid

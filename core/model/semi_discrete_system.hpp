// What a stepper needs of the system it steps: the semi-discrete equation of motion
//   M·ü + C·u̇ + K·u + Gᵀ·λ = f,   g_k = u[plus_k] − u[minus_k] − gap_k <= 0,  λ >= 0,  λ·g = 0
// as an interface, the way Project Chrono's ChTimestepperHHT talks to ChIntegrableIIorder and
// MFEM's ODE solvers to a TimeDependentOperator: its size, its three matrices of one `Matrix`
// type with the products the steppers form (y = A·x, y += s·A·x, xᵀ·A·x, as free functions found
// by argument-dependent lookup), whether C is present, the constant load f (core/model/
// constant_load.hpp, often none), the energy ½vᵀMv + ½uᵀKu (+ the load's potential), the constraint
// rows, and the `Factorization` of the matrices a stepper builds from M, C and K (factor once per
// run, solve in place every step, both without allocation after the first).
//
// Modelled by the tridiagonal system (core/model/second_order_system.hpp: the rod, scenes of
// bodies, 1D models; O(n) Thomas solves) and by a user's sparse model
// (core/model/sparse_system.hpp: a sparse LDLᵀ). The templates written once over the system
// (core/methods/kim_explicit.hpp, noh_bathe.hpp, bathe_composite.hpp, houbolt.hpp,
// wilson_theta.hpp, kr_alpha_recurrence.hpp, core/run/steppers.hpp) are constrained by it, so a
// third system (a SIMD lane type's, say) learns what it must provide from this header alone.
//
// What the concept leaves out on purpose: the tridiagonal system's named walls (contact_dof,
// gap, far_contact_dof, far_gap), through which the paper's scene runs its O(1) contact fast
// paths bit for bit as it always has; they belong to that system's steppers, not to the
// interface.
#pragma once

#include <Eigen/Core>
#include <concepts>
#include <vector>

#include "core/model/constant_load.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/sparse_factorization.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

template <class System>
concept SemiDiscreteSystem = requires(const System& system, const typename System::Matrix& matrix,
                                      typename System::Factorization& factorization,
                                      const typename System::Factorization& factored,
                                      const Eigen::VectorXd& x, Eigen::VectorXd& y, double s) {
  { system.size() } -> std::convertible_to<Eigen::Index>;
  { system.has_damping() } -> std::same_as<bool>;
  { system.energy(x, x) } -> std::same_as<double>;
  { system.mass } -> std::convertible_to<const typename System::Matrix&>;
  { system.damping } -> std::convertible_to<const typename System::Matrix&>;
  { system.stiffness } -> std::convertible_to<const typename System::Matrix&>;
  { system.constraints } -> std::convertible_to<const std::vector<Constraint>&>;
  { system.load } -> std::convertible_to<const ConstantLoad&>;
  multiply(matrix, x, y);
  multiply_add(matrix, s, x, y);
  { quadratic_form(matrix, x) } -> std::same_as<double>;
  { factorization.factor(matrix) } -> std::same_as<bool>;
  factored.solve_in_place(y);
};

static_assert(SemiDiscreteSystem<SecondOrderSystem>);
static_assert(SemiDiscreteSystem<SparseSystem>);

}  // namespace impactid

// One integrator for every implicit method here (backward Euler, Newmark, HHT-α,
// generalized-α): the one-step family of ImplicitCoefficients, solved in acceleration form
//   [(1−α_m)·M + (1−α_f)·(g1·Δt·C + b1·Δt²·K)]·a₁ = rhs,
// with the contact of eqs 16–17 as a one-unknown complementarity problem:
//   1. predict a₁* without a new contact force;
//   2. if the contact dof would penetrate (u_c > gap), solve for the λ₁ > 0 that puts it on the
//      wall, a₁ = a₁* − w·λ₁·A⁻¹·e_c; otherwise λ₁ = 0 (a tensile λ is released).
// The effective matrix A is constant, so it is factored once in initialize() together with the
// contact influence vector A⁻¹·e_c, and every step is O(n) with no allocation. When the contact
// dof is the last unknown (the rod's wall end), step 2 costs nothing extra: the forward sweep of
// the solve already gives a₁*'s last entry, the contact sets that entry, and one back
// substitution then yields a₁ — which is a₁* − w·λ₁·A⁻¹·e_c, since the back substitution is
// linear and A⁻¹·e_c's forward sweep is zero above the last row. The batched kernel
// (core/batch/rod_kernel.cpp) repeats exactly these operations.
//
// With a far wall (SecondOrderSystem::has_far_contact) the step solves the two-constraint
// problem of core/algebra/two_wall_contact.hpp instead, with A⁻¹·e_far also factored in
// initialize(); still O(n) and allocation-free. Without one the step is the single-contact code
// above.
//
// With a list of constraints (SecondOrderSystem::constraints, scenes of several bodies) the step
// predicts the contact-free acceleration, computes each constraint's violation, and solves the
// constraints together as the complementarity problem of core/algebra/contact_lcp.hpp, with the
// columns A⁻¹·G_kᵀ and the matrix b1·Δt²·G·A⁻¹·Gᵀ factored in initialize(). A column is zero
// outside the bodies its constraint touches (A has no coupling between bodies), so the correction
// costs the size of those bodies per active constraint. The constraint holds at the end of the
// step, where its multiplier is reported, as for the single wall.
//
// Written once with the sparse integrator (core/methods/sparse_integrators.hpp): the predictors,
// the α-weighted right-hand side and the update (core/methods/implicit_update.hpp, over any
// core/model/semi_discrete_system.hpp). Why the contact between them stays one class per system:
// here the correction is a stored column A⁻¹·G_kᵀ times the force, on the rows where the column
// is non-zero (and the single wall's O(1) shortcut through the forward sweep, which only a
// tridiagonal factorisation has); on a sparse model it is one more solve with Gᵀ·μ as right-hand
// side, because the columns are dense there. The two are different floating-point operations, so
// one template choosing between them would still hold both, and moving either system to the
// other's changes the bits of its runs, which the batched kernels (core/batch/rod_kernel.cpp,
// chain_kernel.cpp) and every results file hold fixed.
//
// A modified mass (core/model/rod_scene.hpp: redistributed, singular) leaves the contact DOF
// without mass; the effective matrix keeps its stiffness term there and stays regular, so the
// step is unchanged: the massless DOF meets its static equation, α_f-weighted, with the contact,
// at every step. Only the initial acceleration needs a rule (consistent_acceleration). Its
// velocity and acceleration from the Newmark update feed nothing back without damping (the
// displacement at t + Δt is the static equation's whatever the predictor), and that velocity is
// the method's for an algebraic unknown: the trapezoidal rule's v₊ = 2(u₊ − u)/Δt − v alternates
// ±v for ever once the node stops on the wall. The step reports instead the differences
// v₊ = (u₊ − u)/Δt and a₊ = (v₊ − v)/Δt, as GetFEM's demo_dynamic_contact_1D does; with damping
// at the DOF (its velocity then in its equation) the method's own values are kept.
//
// Thread safety: one object per thread (it holds scratch vectors).
#pragma once

#include <utility>
#include <vector>

#include "core/algebra/contact_lcp.hpp"
#include "core/algebra/tridiagonal.hpp"
#include "core/common/state.hpp"
#include "core/contact/constraint_list_law.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/methods/implicit_update.hpp"
#include "core/methods/method.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {

class ImplicitIntegrator {
 public:
  /// Builds and factors the effective matrix. Returns false if it is singular (e.g. a
  /// non-positive mass), in which case step() must not be called.
  /// `contact` says how the constraints are enforced (core/contact/contact_treatment.hpp; default
  /// Lagrange multipliers).
  bool initialize(const SecondOrderSystem& system, const ImplicitCoefficients& coefficients,
                  double dt, const ContactPenalties& contact = {});

  /// Augmented-Lagrangian iterations since initialize(), and the steps whose iterations reached
  /// the cap before the tolerance (both 0 for the other laws).
  long contact_iterations() const { return list_law_.iterations(); }
  long unconverged_contact_steps() const { return list_law_.unconverged(); }

  /// Advances state from t to t + Δt. The state's acceleration must be consistent with its
  /// displacement and velocity (see consistent_acceleration). Returns true if the contact is
  /// active at t + Δt (λ > 0); the contact dof is then exactly on the wall. With a far wall,
  /// state.far_lambda is its force and the far dof is exactly on it when that is positive (the
  /// return value still tells the main wall's contact only).
  bool step(const SecondOrderSystem& system, State& state);

  /// Shifts of the constraints' gaps for the following steps, zero after initialize(): each
  /// constraint is then kept at G_k·u <= gap_k + offset_k (the far wall at −u_0 <= far_gap +
  /// offset), and its dof snapped there. Indexed as the system's constraint list when it has one;
  /// otherwise [0] is the wall (gap), [1] the far wall (far_gap). For a method that enforces its
  /// constraints on an affine image of the step's end (Wilson-θ, core/methods/wilson_theta.hpp: the
  /// constraint at t + Δt seen from the step to t + θΔt). At zero every bit of a step is as
  /// without them: gap + 0.0 is gap, bit for bit, for every gap but −0.0.
  Eigen::VectorXd& gap_offsets() { return gap_offsets_; }

  /// What initialize() set up, for the batched chain kernel (core/batch/chain_kernel.cpp), which
  /// repeats step_constraints() lane by lane with these numbers: the factorisation of the
  /// effective matrix, the constraint columns A⁻¹·G_kᵀ with the rows where each is non-zero,
  /// and the Delassus matrix b1·Δt²·G·A⁻¹·Gᵀ.
  const TridiagonalFactorization& factorization() const { return factorization_; }
  const Eigen::MatrixXd& constraint_influence() const { return constraint_influence_; }
  const std::vector<std::pair<Eigen::Index, Eigen::Index>>& constraint_rows() const {
    return constraint_rows_;
  }
  const Eigen::MatrixXd& delassus() const { return list_.delassus; }

 private:
  /// Predictors and the contact-free right-hand side (core/methods/implicit_update.hpp) with the
  /// previous step's contact forces, forward-swept (left in formulas_.rhs: its last entry is the
  /// last unknown of the contact-free acceleration; backward_in_place completes it).
  void predict(const SecondOrderSystem& system, State& state);
  bool step_two_walls(const SecondOrderSystem& system, State& state);
  bool step_constraints(const SecondOrderSystem& system, State& state);
  /// a = rhs, u = u* + b1·Δt²·a, v = v* + g1·Δt·a (ImplicitUpdate::update), every dof.
  void update(State& state) const;

  ImplicitCoefficients c_{};
  double dt_ = 0.0;
  TridiagonalFactorization factorization_;
  Eigen::VectorXd contact_influence_;  // A⁻¹·e_c
  Eigen::VectorXd far_influence_;      // A⁻¹·e_far; empty without a far wall
  ImplicitUpdate formulas_;            // u*, v* and the right-hand side, then the acceleration
  Eigen::VectorXd contact_free_;       // the contact-free acceleration (two walls only)
  // The constraint list's columns A⁻¹·G_kᵀ (n × m), the rows [begin, end) where each is
  // non-zero, b1·Δt²·G·A⁻¹·Gᵀ (m × m), and per-step scratch (m).
  Eigen::MatrixXd constraint_influence_;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> constraint_rows_;
  ConstraintListProblem list_;
  Eigen::VectorXd forces_;
  // The contact law: the walls' compliances 1/(w·k), and the list's law (its compliances, and
  // the counter of every solve's Uzawa iterations).
  ContactPenalties contact_;
  double main_compliance_ = 0.0, far_compliance_ = 0.0;
  ConstraintListLaw list_law_;
  Eigen::VectorXd gap_offsets_;  // gap_offsets()
  // Massless DOFs without damping (a modified mass), whose velocity and acceleration the step
  // reports by differences (remember_massless, report_massless), and their values at t.
  std::vector<Eigen::Index> massless_;
  std::vector<double> massless_u_, massless_v_;
  void remember_massless(const State& state);
  void report_massless(State& state) const;
};

/// a solving M·a = f − K·u − C·v − G^T·λ (+ λ_0 at the far dof; f the system's load, if any): the
/// acceleration consistent with the equation of motion. A massless DOF (a modified mass,
/// core/model/rod_scene.hpp: its row of M zero) has no such equation: its acceleration is that of
/// its static equation differentiated twice, a_c = −Σ_{j≠c} K_cj·a_j / K_cc, the contact force held
/// constant (zero for the rod, which starts unstrained).
Eigen::VectorXd consistent_acceleration(const SecondOrderSystem& system, const State& state);

}  // namespace impactid

// Wilson-θ (Wilson, Farhoomand & Bathe 1972, Earthquake Eng. Struct. Dyn. 1:241–252,
// doi:10.1002/eqe.4290010305; core/methods/method.hpp, WilsonThetaParams) stepped by an integrator
// of the single-step implicit family.
//
// The step. The integrator takes the linear-acceleration step (Newmark β = 1/6, γ = ½) of length
// τ = θ·Δt from (u_n, v_n, a_n), which solves equilibrium at t + θΔt for a_θ:
//   u_θ = Q + (τ²/6)·a_θ,   Q = u_n + τ·v_n + (τ²/3)·a_n.
// The state at t + Δt then follows the same linear acceleration back:
//   a_{n+1} = a_n + (a_θ − a_n)/θ,  v_{n+1} = v_n + Δt(a_n + a_{n+1})/2,
//   u_{n+1} = u_n + Δt·v_n + Δt²(2a_n + a_{n+1})/6 = P + Δt²/(6θ)·a_θ,
//   P = u_n + Δt·v_n + Δt²(3 − 1/θ)/6·a_n.
//
// The contact, at t + Δt. The samples are at t + Δt, so that is where the Signorini conditions
// must hold; equilibrium only holds at t + θΔt. Both u_θ and u_{n+1} are affine in a_θ, with
//   u_{n+1} − P = (u_θ − Q)/θ³,
// so a constraint G·u_{n+1} <= gap is the constraint G·u_θ <= G·Q + θ³·(gap − G·P) on the
// integrator's own step: the same constraint with a shifted gap. Each step sets these shifts
// (the integrator's gap_offsets(), one number per constraint) before it solves, so the
// integrator's complementarity problem (single wall, two walls, a constraint list, a sparse
// model alike) gives multipliers λ_θ >= 0 that act in the equilibrium at t + θΔt and are
// complementary to the gaps at t + Δt: λ_θ > 0 only where u_{n+1} is on its wall. Walls are
// then snapped exactly onto it (the affine map leaves the node a few ulps off).
//
// The reported multiplier is that λ_θ: the force that, acting at t + θΔt, keeps the contact at
// t + Δt. It is the one value that satisfies λ >= 0, no penetration and λ·gap = 0 together at
// each sample. The multiplier interpolated like the acceleration, (1 − 1/θ)·λ_n + λ_θ/θ, is >= 0
// too (θ >= 1), but stays positive for a step after a release, when the node has left the wall.
// Enforcing the constraint at t + θΔt instead (the plain step with the integrator's own contact)
// would hold it only there: u_{n+1} = P + (gap − Q)/θ³ misses the wall, in front of it or beyond,
// whenever the node moves during the step, and a sample would report λ > 0 off the wall.
//
// The price: with the contact at the samples Wilson-θ chatters on the wall and gains energy. From t
// to t + Δt its update is the linear-acceleration step (β = 1/6, γ = ½), so the force that puts a
// node on the wall at t + Δt changes its velocity by 3/Δt times the displacement it takes away
// (γ/β = 3; the trapezoidal rule's 2 reflects a free mass at its own speed): a free mass arriving
// at v with the wall δ ahead leaves at −2v + 3δ/Δt, whatever θ (tests/wilson_theta_test.cpp,
// AFreeMassLeavesTheWallUpToTwiceAsFastAsItCame). On the paper's scene the runs tried grow past the
// default energy bound and end `unstable`. With the constraint at t + θΔt instead the energy stays
// bounded, but the node stands beyond the wall at the samples, so the sample's Signorini conditions
// fail: that variant is not offered.
//
// Penalty and augmented Lagrangian, where the constraint is enforced: on the extended step's
// shifted gap, by the integrator's own laws (core/contact/contact_treatment.hpp). The sample's
// penetration g_{n+1} is 1/θ³ of the extended step's on the shifted gap, so the extended step's
// springs are k/θ³: its force k/θ³·(θ³·g_{n+1}) is then the spring k of the sample's own
// penetration, λ = k·max(0, g_{n+1}) at every sample, as the single-step methods' at the end of
// their step. The augmented Lagrangian's Uzawa iterations run on the same shifted problem (counted)
// and reach the Lagrange multipliers; neither law snaps the node onto its wall.
//
// Works with ImplicitIntegrator (tridiagonal systems: the rod, scenes of bodies) and
// SparseImplicitIntegrator (a user's model) alike. Per step: one solve of the factorised matrix
// M + (τ/2)·C + (τ²/6)·K, O(n) extra vector work, no allocation once the state's sizes are set.
//
// Thread safety: one object per thread (it holds the extended step's state).
#pragma once

#include <type_traits>

#include "core/common/state.hpp"
#include "core/contact/constraint_set.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/methods/method.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/semi_discrete_system.hpp"

namespace impactid {

// System: SecondOrderSystem with ImplicitIntegrator, SparseSystem with SparseImplicitIntegrator.
template <class Integrator, SemiDiscreteSystem System>
class WilsonTheta {
 public:
  /// Factors the extended step's effective matrix. False if it is singular (or not positive
  /// definite, for the sparse integrator, whose failure() then says why). `contact`: the law of
  /// every constraint, its springs k as at the sample (the header).
  bool initialize(const System& system, const WilsonThetaCoefficients& coefficients, double dt,
                  const ContactPenalties& contact = {}) {
    theta_ = coefficients.theta;
    dt_ = dt;
    lagrange_ = contact.lagrange();
    return extended_.initialize(system, coefficients.extended, theta_ * dt,
                                extended_springs(contact, theta_));
  }

  /// Advances state from t to t + Δt; its acceleration must be consistent with u and v (as for
  /// the integrators). Returns true if a constraint is active at t + Δt.
  bool step(const System& system, State& state) {
    mid_ = state;  // the vectors keep their storage once sized: no allocation after the first step
    set_gap_offsets(system, state);
    const bool active = extended_.step(system, mid_);

    const Eigen::Index n = state.u.size();
    const double dt = dt_, inverse_theta = 1.0 / theta_;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double a0 = state.a[i];
      const double a1 = a0 + (mid_.a[i] - a0) * inverse_theta;
      state.u[i] += dt * state.v[i] + (dt * dt / 6.0) * (2.0 * a0 + a1);
      state.v[i] += 0.5 * dt * (a0 + a1);
      state.a[i] = a1;
    }
    state.lambda = mid_.lambda;
    state.far_lambda = mid_.far_lambda;
    state.multipliers = mid_.multipliers;
    state.t += dt;
    snap(system, state);
    return active;
  }

  /// The state at t + θΔt of the last step: equilibrium there, displacements on the shifted
  /// walls (for tests).
  const State& extended_state() const { return mid_; }
  const Integrator& extended() const { return extended_; }
  /// Augmented-Lagrangian iterations since initialize(), and steps that ended at the cap.
  long contact_iterations() const { return extended_.contact_iterations(); }
  long unconverged_contact_steps() const { return extended_.unconverged_contact_steps(); }

 private:
  // gap' − gap for every constraint, from Q and P at its dofs (file comment).
  void set_gap_offsets(const System& system, const State& s) {
    const double dt = dt_, tau = theta_ * dt, theta3 = theta_ * theta_ * theta_;
    const double p_weight = dt * dt * (3.0 - 1.0 / theta_) / 6.0, q_weight = tau * tau / 3.0;
    const auto q = [&](Eigen::Index i) { return s.u[i] + tau * s.v[i] + q_weight * s.a[i]; };
    const auto p = [&](Eigen::Index i) { return s.u[i] + dt * s.v[i] + p_weight * s.a[i]; };
    // G·x − gap <= 0 at t + Δt  ⇔  G·u_θ <= G·Q + θ³·(gap − G·P).
    const auto offset = [&](double gq, double gp, double gap) {
      return gq + theta3 * (gap - gp) - gap;
    };
    Eigen::VectorXd& offsets = extended_.gap_offsets();
    for (std::size_t k = 0; k < system.constraints.size(); ++k) {
      const Constraint& c = system.constraints[k];
      double gq = 0.0, gp = 0.0;
      if (c.plus >= 0) gq += q(c.plus), gp += p(c.plus);
      if (c.minus >= 0) gq -= q(c.minus), gp -= p(c.minus);
      offsets[static_cast<Eigen::Index>(k)] = offset(gq, gp, c.gap);
    }
    if constexpr (std::is_same_v<System, SecondOrderSystem>) {
      if (system.has_constraint_list()) return;
      if (system.has_contact()) {
        offsets[0] = offset(q(system.contact_dof), p(system.contact_dof), system.gap);
      }
      if (system.has_far_contact()) {  // −u_far <= far_gap
        const Eigen::Index far = system.far_contact_dof;
        offsets[1] = offset(-q(far), -p(far), system.far_gap);
      }
    }
  }

  // The extended step's springs: k/θ³ for a spring k at the sample, whose penetration is 1/θ³
  // of the extended step's on the shifted gap (the header).
  static ContactPenalties extended_springs(ContactPenalties contact, double theta) {
    const double theta3 = theta * theta * theta;
    contact.main /= theta3;
    contact.far /= theta3;
    for (double& k : contact.listed) k /= theta3;
    return contact;
  }

  // Walls exactly on their (unshifted) gap where they push at t + Δt (Lagrange's multipliers; the
  // other laws leave the node where the force put it).
  void snap(const System& system, State& s) const {
    if (!lagrange_) return;
    snap_walls(system.constraints, s.multipliers, s.u);
    if constexpr (std::is_same_v<System, SecondOrderSystem>) {
      if (system.has_constraint_list()) return;
      if (s.lambda > 0.0) s.u[system.contact_dof] = system.gap;
      if (s.far_lambda > 0.0) s.u[system.far_contact_dof] = -system.far_gap;
    }
  }

  double theta_ = 1.4;
  double dt_ = 0.0;
  bool lagrange_ = true;
  Integrator extended_;
  State mid_;
};

}  // namespace impactid

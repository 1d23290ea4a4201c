// How a unilateral contact g = u[plus] − u[minus] − gap <= 0 is enforced: by a Lagrange
// multiplier (the paper's, and the default), by a penalty force, or by an augmented Lagrangian.
// The laws' names, parameters and validation are their registry's
// (core/contact/contact_law_registry.hpp); this file is their arithmetic.
// Every method enforces the constraint where its Lagrange multiplier does (core/methods/method.hpp:
// the end of the step, and the end of each sub-step for the composite schemes; central difference
// at t + Δt through its forward-increment force at t), and each law changes only the step's
// complementarity problem, g = p − D·μ (p the contact-free penetration, D the Delassus matrix,
// μ = w·λ the weighted forces; core/algebra/contact_lcp.hpp):
// - **lagrange**: g <= 0, μ >= 0, μ·g = 0. The gap holds exactly, λ >= 0.
// - **penalty**: λ = k·max(0, g), the force of a spring of stiffness k that acts once the node
//   penetrates. For the implicit methods it is the same problem with D + diag(1/(w·k)) (the
//   spring solved with the step, so the step stays unconditionally stable); the penetration is
//   then λ/k. For central difference it is the explicit force λ_t = k·max(0, g(u_t)) at t, the
//   penalty of explicit codes, and for the explicit multi-stage schemes (Noh–Bathe, Kim's) each
//   stage's at the displacement its equilibrium is taken at
//   (core/contact/explicit_stage_contact.hpp): the spring raises the highest frequency, so the
//   stable step shrinks with k (core/contact/stable_step.hpp computes it, and the run reports it).
//   KR-α's springs are solved with its forward increment, as the implicit methods' with their step:
//   it stays unconditionally stable (core/methods/kr_alpha.hpp says why its spring cannot be
//   explicit).
// - **augmented-lagrangian**: Uzawa's iterations on the penalty problem of every method, the
//   explicit ones' forward increments included: μ_{j+1} solves the penalty problem around μ_j, (D +
//   C)·μ = p + C·μ_j with C = diag(1/(w·k)), from μ_0 = 0 (the penalty solution) until the largest
//   penetration is at most `augmented_tolerance` times the largest contact-free one, or
//   `augmented_max_iterations` are done. μ converges to the Lagrange multiplier: its error shrinks
//   by 1/(1 + w·k·d) per iteration for a single contact (d = D's entry), so a stiffer k converges
//   faster. The iterations are counted in the run summary.
// - **paoli-schatzman** (central difference only): Lagrange's multiplier with the gap held on
//   (u_{n+1} + e·u_{n−1})/(1 + e), e the coefficient of restitution; resolved as Lagrange's law
//   with `restitution` e, which central difference turns into a shift of each gap
//   (core/contact/paoli_schatzman_law.hpp). At e = 0 it is Lagrange's law, bit for bit.
//
// The penalty stiffness k [N/mm] is `penalty_stiffness` when given, otherwise `penalty_factor`
// times the contact dof's stiffness K_cc (for a constraint between two bodies, the smaller of its
// two dofs'). Default factor 1: k = K_cc = E·A/h for the rod, the stiffness of the element at the
// wall. Why 1: the penetration under the rod's pressure ρ·c·v0·A is then h·v0/c, the fraction v0/c
// of an element, and central difference's stable Courant number with the spring at the wall is
// √(2/(2 + factor)) = 0.82, above the default 0.5: the default penalty runs stable with every
// default method. A factor of 100 divides the penetration by 100 and that Courant number falls to
// √(2/102) = 0.14.
//
// Thread safety: values and pure functions.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "core/algebra/two_wall_contact.hpp"
#include "core/contact/augmented_lagrangian_law.hpp"
#include "core/contact/contact_law_registry.hpp"
#include "core/contact/penalty_law.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

/// A treatment resolved for one system: the law and each constraint's penalty stiffness k [N/mm]
/// (unused for lagrange). What the integrators' initialize() take.
struct ContactPenalties {
  ContactLaw law = ContactLaw::lagrange;
  double main = 0.0;           ///< the named wall's (SecondOrderSystem::contact_dof)
  double far = 0.0;            ///< the named far wall's
  std::vector<double> listed;  ///< one per SecondOrderSystem::constraints entry
  double tolerance = 1e-6;
  int max_iterations = 100;
  /// Paoli–Schatzman's e (core/contact/paoli_schatzman_law.hpp), with `law` then Lagrange's; 0
  /// for every other law.
  double restitution = 0.0;

  bool lagrange() const { return law == ContactLaw::lagrange; }
  /// The registry's ContactLawDescriptor::explicit_force, as a comparison the step loops can
  /// afford (tests/contact_law_registry_test.cpp holds the two equal).
  bool explicit_force() const { return law == ContactLaw::penalty; }
};

ContactPenalties resolve_contact(const ContactTreatment& treatment,
                                 const SecondOrderSystem& system);
/// The same for a model of sparse matrices: its constraint list (main and far unused).
ContactPenalties resolve_contact(const ContactTreatment& treatment, const SparseSystem& system);

/// One contact's weighted force under a law other than Lagrange's, from its contact-free
/// penetration p > 0, the penetration d a unit weighted force removes, and its compliance
/// 1/(w·k): p/(d + compliance) for the penalty, Uzawa's iterations (counted in `iterations`) for
/// the augmented Lagrangian.
double single_contact_force(double p, double d, double compliance,
                            const ContactPenalties& penalties, ContactIterations& iterations);

/// The force on a massless contact DOF (a modified mass, core/model/rod_scene.hpp) that its static
/// equation K_cc·u_c + Σ K_cj·u_j ± λ = 0 gives under the law, from the penetration p > 0 of its
/// contact-free static position and its stiffness K_cc, with the wall's spring k (penalty and
/// augmented Lagrangian): Lagrange's λ = K_cc·p puts it on the wall; the laws with a spring solve
/// it with the spring in the same static equation (single_contact_force with d = 1/K_cc), the
/// only form that stays stable as k grows, since a DOF without mass cannot take an explicit force.
double massless_contact_force(double p, double stiffness, double spring,
                              const ContactPenalties& penalties, ContactIterations& iterations);

/// The two walls' problem (core/algebra/two_wall_contact.hpp) under a law other than Lagrange's,
/// with each wall's compliance added to its diagonal.
TwoWallForces two_wall_contact_forces(double p_main, double p_far, double d_main, double d_far,
                                      double c_main_far, double c_far_main, double main_compliance,
                                      double far_compliance, const ContactPenalties& penalties,
                                      ContactIterations& iterations);

}  // namespace impactid

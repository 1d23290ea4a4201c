// What a run of a user's model (core/model/model_scene.hpp) is measured against, sampled at its
// samples t_i = i·Δt (i = 1..N):
// - the history the user supplies (ReferenceHistory: a CSV file of the scene), linearly
//   interpolated in t between its samples, its own values where a sample time matches to 1e-9·Δt
//   (a history written at the run's samples, as `impactid export-model` writes the exact solution
//   of a built-in scene, is taken as it is); or
// - a converged solution: the scene run by a reference method at Δt/2^k, k = 1, 2, …, until the
//   primary contact's pressure and velocity change by less than a tolerance between two
//   halvings, in the form of eq. 18 (Σ|x_k − x_{k−1}| / Σ|x_k| over the samples). The reference's
//   sample at t_i is the mean of the refined run's samples over the run's step centred on t_i,
//   (t_i − Δt/2, t_i + Δt/2]: the contact force's impulse over that step divided by Δt. Why not
//   the refined sample at t_i itself: an impact stops the contact DOF within one refined step,
//   by a force of the DOF's momentum over that step, which doubles at every halving; where the
//   impact falls on a sample time (the block at Courant 0.5) the sampled reference then never
//   converges, while its impulse does. Halvings whose run is not ok (central difference above its
//   stability limit) are passed over until one is.
//
// The reference method (model_reference_defaults): central difference when M is diagonal, HHT
// α = −0.3 (δ = −α) otherwise. Why central difference: the semi-discrete model with a Lagrange
// contact needs an impact law at the contact DOF, and each integrator brings its own. Carpenter's
// forward-increment multiplier stops the contact DOF at the wall (an inelastic impact of the
// node, the persistent-contact solution), which converges as Δt → 0; the implicit family's
// end-of-step constraint reverses the node's velocity at every re-contact, so its contact force
// chatters at the refined step and the samples keep changing: on the exported paper's rod and the
// shipped block HHT's refinement does not converge where central difference's does (an HHT
// reference ends unconverged or unverified in tests/model_reference_test.cpp,
// AnHhtReferenceIsUnverifiedAndFailsTheCommand). With a consistent mass (no central difference) the
// HHT reference may therefore end unconverged, and says so.
//
// The check (issue 34, item 4): a reference computed by one method favours that method, and the
// semi-discrete model's limit depends on each method's impact law (above). So a converged
// reference is checked by a second method of another family (check_method_for: backward Euler,
// or for backward Euler central difference/HHT), run at Δt/2^k, k = 1, 2, …, each level from the
// second extrapolated in Δt (Richardson, by the check method's order q: x_k + (x_k − x_{k−1}) /
// (2^q − 1)) and compared with the reference, in eq. 18's form on the primary contact (the larger
// of pressure's and velocity's difference), until they agree within agreement_tolerance() or the
// halvings (max_refinements) run out. Only then is the reference trusted. Backward Euler's
// end-of-step constraint leaves the contact DOF at rest on the wall, the same persistent-contact
// limit as central difference's forward-increment multiplier, reached from the implicit side;
// HHT's reverses the DOF's velocity and converges to another limit, which the check exposes. Why
// extrapolate: backward Euler is first order, and its runs alone would need further halvings, each
// costing as much as all the halvings before it, to come as close to the reference.
// The reference's estimated error, `error`, is the larger of its last change and that difference:
// every ε measured against it is uncertain by about that much. An untrusted reference makes every
// run measured against it `unverified` (metrics/verdict.hpp) and `impactid simulate` and `compare`
// exit with status 3.
//
// Unlike a scene of bodies (core/reference/scene_reference.hpp), a model's mesh is the user's and
// cannot be refined: the converged solution is that of the semi-discrete model, not of the
// continuum.
//
// Thread safety: values; model_reference() is reentrant.
#pragma once

#include <string>
#include <vector>

#include "core/model/model_scene.hpp"
#include "core/reference/scene_reference.hpp"

namespace impactid {

struct ModelReference {
  ModelScene scene;                      ///< what it is the reference of (a cache key)
  ReferenceOptions options;              ///< and with which options
  std::vector<ContactSamples> contacts;  ///< Model::contacts order; empty vectors: none
  /// −1: the supplied history; k >= 1: the converged solution at Δt/2^k (or the last computed).
  int refinements = -1;
  double dt = 0.0;  ///< the reference's step (the supplied history's: NaN)
  /// The relative change at the last halving (NaN for a supplied history).
  double change = std::numeric_limits<double>::quiet_NaN();
  bool converged = true;  ///< false when max_refinements ran out or a refined run failed
  std::string message;    ///< why not converged, or why not usable

  /// The check of a converged reference by a second method (see above); has_check false for a
  /// supplied history, and when the reference itself did not converge (it is untrusted anyway).
  bool has_check = false;
  MethodParams check_method;
  int check_refinements = 0;  ///< the check's last level, Δt/2^k
  /// The check's relative change at its last level (not extrapolated).
  double check_change = std::numeric_limits<double>::quiet_NaN();
  bool check_converged = false;  ///< whether the check came to agree (disagreement <= tolerance)
  /// Σ|x − x_check| / Σ|x| of the primary contact against the check's last extrapolated level,
  /// the larger of pressure's and velocity's; NaN when the check had fewer than two levels.
  double disagreement = std::numeric_limits<double>::quiet_NaN();
  /// The estimated error: max(change, disagreement) of a converged reference (NaN when either is
  /// missing), NaN for a supplied history.
  double error = std::numeric_limits<double>::quiet_NaN();

  /// A supplied history that covers the run; or a converged reference whose check came to agree.
  bool trusted() const;
  /// The largest disagreement of a trusted reference: 10 times the convergence tolerance (1e-2 at
  /// a model's default), an order looser than the reference's own change, because the check's
  /// extrapolated limit is itself an estimate, of a first-order method's limit, not a converged
  /// solution (the commit that added the check has the measurements).
  double agreement_tolerance() const { return 10.0 * options.tolerance; }

  /// Whether the primary contact has samples to compare with.
  bool usable(int primary) const;
  /// "supplied: FILE" or "converged: hht at dt/2^k = … s, relative change …; checked by …".
  std::string description() const;
  /// "; checked by backward-euler at dt/2^k, extrapolated: difference … (at most …), estimated
  /// error …", or "".
  std::string check_text() const;
};

/// Options of a model's converged reference: central difference when M is diagonal, else HHT
/// α = −0.3 (see above); tolerance 1e-3; at most 10 halvings (1024 times the run's steps; each
/// halving doubles the cost).
ReferenceOptions model_reference_defaults(const Model& model);

/// The check's method for a reference method, and its order of accuracy (for the extrapolation):
/// backward Euler (1), or for backward Euler central difference (2) when M is diagonal and HHT
/// α = −0.3 (2) otherwise.
struct CheckMethod {
  MethodParams method;
  int order = 1;
};
CheckMethod check_method_for(const MethodParams& method, const Model& model);

/// The reference of a valid model scene. Never throws: a reference that cannot be had is not
/// usable(), with the reason in `message`.
/// `run` runs the refined scenes (core/run/references.hpp passes simulate()).
ModelReference model_reference(const ModelScene& scene, const ReferenceOptions& options,
                               const ReferenceRun& run);

}  // namespace impactid

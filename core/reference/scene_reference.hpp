// What a run of a scene of bodies is measured against, sampled at its samples t_i = i·Δt
// (i = 1..N), chosen in this order:
//   - the exact solution of the clamped bar released onto an obstacle (Doyen, Ern & Piperno 2011,
//     core/reference/clamped_bar_exact.hpp) when the scene is in that benchmark's form
//     (clamped_bar_params below); its conventions are the scene's left wall's (+x away from the
//     obstacle, the pressure compressive-positive), so its values are taken as they are;
//   - the exact solution of the bouncing bar (Doyen, Ern & Piperno 2011,
//     core/reference/bouncing_bar_exact.hpp) when the scene is in that benchmark's form
//     (bouncing_bar_params below), with the same conventions;
//   - the exact solution of the chain (core/reference/chain_exact.hpp) when the scene has no
//     damping, which that solution leaves out, and its bodies start free and unstrained
//     (bodies_start_free: no clamped end, no initial displacement, which it leaves out too);
//   - otherwise a converged numerical solution (issue 18):
// the scene run by a reference method with every segment's mesh and the step refined together,
// h/2^k and Δt/2^k (the same Courant number), until the primary contact's pressure and velocity
// change by less than a tolerance between two refinements, in the form of eq. 18
// (Σ|x_k − x_{k−1}| / Σ|x_k| over the samples). A refined run's sample t_i is its step i·2^k,
// and a contact's nodes are the same material points at every refinement, so no interpolation
// enters.
//
// Why the mesh too: refining the step alone does not converge at contact samples. The
// semi-discrete model with Lagrange contact chatters: its contact node bounces on the wall or
// the other body at the scale of the step, so the sampled values keep changing however small the
// step. Refined together, mesh and step converge to the continuum solution, the one the exact
// solution describes, and faster with stiffness damping, which smooths the fronts. Each halving
// costs four times the previous run.
//
// Thread safety: values; scene_reference() is reentrant.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/common/run_record.hpp"
#include "core/methods/method.hpp"
#include "core/model/scene.hpp"
#include "core/reference/bouncing_bar_exact.hpp"
#include "core/reference/clamped_bar_exact.hpp"
#include "core/reference/reference_run.hpp"

namespace impactid {

struct ReferenceOptions {
  /// The method of a converged reference: HHT with α = −0.3, δ = −α (second order, and damped
  /// enough that the refined runs do not chatter on the contacts).
  MethodParams method = HhtParams{.alpha = -0.3};
  /// Largest relative change of the primary contact's pressure or velocity at the last
  /// refinement. > 0; default 1e-2 (reached within the default halvings on a damped scene; see
  /// above).
  double tolerance = 1e-2;
  /// Most halvings of the mesh and the step. >= 1; default 5 (1024 times the run's cost).
  int max_refinements = 5;
};
/// Equal options give the same reference (methods compared by kind and coefficients).
bool operator==(const ReferenceOptions& a, const ReferenceOptions& b);

/// Which exact solution a reference is, if any.
enum class SceneExact {
  none,          ///< a converged numerical solution
  chain,         ///< ChainExact (core/reference/chain_exact.hpp)
  clamped_bar,   ///< ClampedBarExact (core/reference/clamped_bar_exact.hpp)
  bouncing_bar,  ///< BouncingBarExact (core/reference/bouncing_bar_exact.hpp)
};

/// The clamped bar's parameters of a scene in the form of Doyen, Ern & Piperno's first benchmark:
/// one body of one segment, a contact wall on the left at gap 0, a clamped right end, an initial
/// displacement [a, 0] with a > 0, no initial velocity, no damping (any mass matrix, any step).
/// L, E, ρ are the segment's and a the displacement's left value; the scene's one contact
/// (wall_left) then has the solution's pressure and contact-end velocity. Nothing for any other
/// scene.
std::optional<ClampedBarParams> clamped_bar_params(const Scene& scene);

/// The bouncing bar's parameters of a scene in the form of Doyen, Ern & Piperno's second
/// benchmark: one body of one segment at rest and undisplaced, gravity toward a contact wall on
/// the left (Scene::gravity = −g < 0) whose gap is the benchmark's drop d = g·(3L/c)²/2 (within a
/// relative 1e-9), no right wall, no damping (any mass matrix, any step). L, E, ρ are the
/// segment's; the scene's one contact (wall_left) then has the solution's pressure and lower-end
/// velocity (+x up, away from the ground). Nothing for any other scene, a drop of another height
/// included (another ratio t_f·c/L is another solution, which BouncingBarExact does not cover).
std::optional<BouncingBarParams> bouncing_bar_params(const Scene& scene);

struct SceneReference {
  Scene scene;                           ///< what it is the reference of (a cache key)
  ReferenceOptions options;              ///< and with which options
  std::vector<ContactSamples> contacts;  ///< scene_contacts() order
  /// 0: an exact solution (`exact` says which); k >= 1: the converged solution at h/2^k and Δt/2^k.
  int refinements = 0;
  SceneExact exact = SceneExact::none;
  /// The relative change at the last refinement (NaN for the exact solution).
  double change = std::numeric_limits<double>::quiet_NaN();
  /// False when max_refinements were used without reaching the tolerance, or a refined run
  /// was not ok: the reference is then the last one computed, and the message says why.
  bool converged = true;
  std::string message;

  /// Whether there are samples to compare with: false when even the first refined run was not
  /// ok, or the exact solution could not be computed (more events than ChainExact allows).
  bool usable() const { return !contacts.empty(); }

  /// "exact solution of the chain (…)", "exact solution of the clamped bar (…)" or "converged: hht
  /// at h/2^k and dt/2^k, relative change …".
  std::string description() const;
};

/// Σ|a − b| / Σ|a| (eq. 18's form) of two refinements' samples, 0 when both are zero.
double relative_change(const std::vector<double>& a, const std::vector<double>& b);

/// The reference of a valid scene: exact when the scene is the clamped bar's or undamped with
/// bodies that start free; otherwise converged. Never
/// throws for a valid scene: a reference that cannot be had is !usable(), with the reason in
/// `message`.
/// `run` runs the refined scenes (core/run/references.hpp passes simulate()).
SceneReference scene_reference(const Scene& scene, const ReferenceOptions& options,
                               const ReferenceRun& run);

}  // namespace impactid

// One rod-impact simulation: assemble the scene, run one method over the time grid, record the
// contact node at every sample t_i = i·Δt (i = 1..N; the initial state is not a sample) and
// return a summary. Numerical failure is an outcome, not an exception: an unstable run ends
// early with status `unstable`, its remaining samples NaN.
//
// Thread safety: simulate() is reentrant; give each thread its own SimulationWorkspace.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "core/common/run_record.hpp"
#include "core/common/state.hpp"
#include "core/methods/method.hpp"
#include "core/model/rod_scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/reference/model_reference.hpp"
#include "core/reference/scene_reference.hpp"
#include "core/run/steppers.hpp"

namespace impactid {

struct RunOptions {
  /// A run is `unstable` as soon as its energy exceeds this multiple of the initial energy
  /// ½vᵀMv + ½uᵀKu. The energy is ½vᵀMv + ½uᵀKu for every method but central difference and KR-α,
  /// whose own discrete energies (central_difference_energy,
  /// core/methods/central_difference_recurrence.hpp; KrAlphaExplicit::energy,
  /// core/methods/kr_alpha.hpp) stay bounded where the plain one grows or swings with no
  /// instability (central difference at the magic time step, with a mode that changes no nodal
  /// value; KR-α at large Courant numbers). Without external work the exact energy never grows, and
  /// the stable methods here stay close to it (central difference's central-velocity energy rises a
  /// little at impact, the implicit methods dissipate), while an unstable mode grows geometrically,
  /// so the bound separates the two long before any value overflows. > 1.
  double energy_growth_limit = 1.5;
  /// The energy bound is checked every this many steps and at the last step (1: every step). The
  /// energy costs two O(n) products, a sizeable part of a step (docs/performance.md); an unstable
  /// mode grows geometrically, so it is caught at most this many steps late. Non-finite values are
  /// caught at every step. >= 1.
  int energy_check_interval = 16;
  /// Record the contact-node displacement and the energy at every sample (time histories).
  /// Otherwise the trace holds pressure and velocity only: all the indicators need.
  bool record_history = false;
  /// Before the impact the rod moves rigidly, u = v0·t, v = v0, a = 0, which every method here
  /// reproduces exactly (K·1 = 0). When set, and nothing slows the rod in flight (no
  /// mass-proportional damping), the steps up to shortly before the impact are filled in rather
  /// than computed; the results differ from stepped ones by round-off only.
  bool skip_free_flight = true;
  /// How every contact is enforced (core/contact/contact_law_registry.hpp lists the laws):
  /// Lagrange multipliers by default; the penalty and the augmented Lagrangian on every scene,
  /// with every method.
  ContactTreatment contact;
};

/// Per-thread storage reused from run to run: after the first run of a given size, further
/// runs of that size allocate nothing in the step loop.
struct SimulationWorkspace {
  Steppers<SecondOrderSystem> tridiagonal;  ///< the rod's, a scene of bodies', a 1D model's
  Steppers<SparseSystem> sparse;             ///< a user's model with sparse matrices
  /// The steppers for `System`: simulate() chooses by the type of the system it runs.
  template <SemiDiscreteSystem System>
  Steppers<System>& steppers() {
    if constexpr (std::is_same_v<System, SparseSystem>) {
      return sparse;
    } else {
      return tridiagonal;
    }
  }
  State state;
  ContactTrace trace;
  /// The reference of the last scene of bodies evaluated with this workspace
  /// (study/studies/evaluation.cpp): a sweep over method parameters keeps one scene, whose
  /// reference is then computed once per thread.
  std::optional<SceneReference> reference;
  /// The same for a user's model (study/studies/evaluation.cpp): the last one used.
  std::optional<ModelReference> model_reference;
  /// The ones used before it, most recent last (at most kEarlierModelReferences): a work-precision
  /// study alternates between its Courant numbers' references, and a model's reference with its
  /// check by a second method takes many refined runs.
  std::vector<ModelReference> earlier_model_references;
  static constexpr std::size_t kEarlierModelReferences = 8;
};

/// Runs scene and method (both must be valid: see validate()): simulate(assemble(scene), …), the
/// set-up time including the assembly. The trace is left in workspace.trace.
RunSummary simulate(const RodScene& scene, const MethodParams& method, const RunOptions& options,
                    SimulationWorkspace& workspace);

/// Runs an assembled scene (core/model/scene_assembly.hpp: the rod's, or a scene of bodies') with a
/// valid method: the one run of every scene. The trace is left in workspace.trace, with every
/// contact's samples when the scene asks for them (AssembledScene::contact_columns). A scene of
/// bodies in the paper's form (one body, one segment, a right wall) gives the same numbers as
/// simulate(RodScene) of that rod, bit for bit.
RunSummary simulate(const AssembledScene& scene, const MethodParams& method,
                    const RunOptions& options, SimulationWorkspace& workspace);

/// How many samples of a run are rigid free flight to be filled in rather than stepped: before
/// the first contact every method computes u = v0·t, v = v0, a = 0 exactly (K·1 = 0 in each
/// body), so the samples up to shortly before it are filled in when options.skip_free_flight is
/// set and nothing slows a body in flight (rigid_flight). prepare_run() passes rigid_flight false
/// for a scene whose bodies do not start free and unstrained (AssembledScene::starts_free false
/// or an initial displacement): a clamped end or an initial strain makes the flight anything but
/// u = v0·t, so such a scene is stepped from t = 0. Central difference's λ at t_i looks
/// ahead to t_{i+1}, hence one step of margin beyond the last sample before the contact.
/// Shared by simulate() and the batched kernels, which must fill in the same samples.
long free_flight_samples(double first_contact_time, double dt, long step_count, bool rigid_flight,
                         const RunOptions& options);

/// The part of simulate(AssembledScene) before its step loop: the summary and the trace set up
/// (every sample NaN), the state at t = 0 with its consistent acceleration, and the free flight
/// filled in (the state then at its end, summary.skipped_steps samples written). Returns false
/// with the summary `failed` for run options or a scene that cannot run. Shared with the batched
/// chain kernel (core/batch/batched_chain.hpp), which steps each lane from there.
bool prepare_run(const AssembledScene& scene, const RunOptions& options, ContactTrace& trace,
                 State& state, RunSummary& summary);

}  // namespace impactid

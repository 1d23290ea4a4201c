// The indicators of one run, compared with the exact solution at the samples t_i = i·Δt,
// i = 1..N (see RodImpactExact::at_sample for the convention on jumps). With a far wall the exact
// solution is the periodic two-wall one, and eps_p, eps_v, nop_p, nop_v, p_max and
// contact_episodes still describe the main wall's contact node.
#pragma once

#include <span>

#include "core/common/run_record.hpp"
#include "core/model/rod_scene.hpp"
#include "core/model/scene.hpp"
#include "core/reference/scene_reference.hpp"

namespace impactid {

struct IndicatorOptions {
  /// Minimum prominence of a counted peak, as a fraction of ρ·c·v0 (pressure) and of |v0|
  /// (velocity). See peak_count.hpp for the rule and why. > 0.
  double peak_prominence = 1e-6;
  /// A scene of bodies with damping is measured against a converged numerical solution
  /// (core/reference/scene_reference.hpp), refined until its primary contact's pressure and
  /// velocity change by less than this between two halvings of the mesh and the step. > 0.
  double reference_tolerance = 1e-2;
};

/// All NaN when the run is not ok: an unstable run's numbers are not results.
struct Indicators {
  double eps_p;             ///< eq. 18 for the contact pressure
  double eps_v;             ///< eq. 18 for the contact-node velocity
  double nop_p;             ///< number of peaks of the pressure
  double nop_v;             ///< number of peaks of the contact-node velocity
  double p_max;             ///< largest sampled pressure [MPa]
  double p_max_ratio;       ///< p_max / (ρ·c·v0)
  double contact_episodes;  ///< maximal runs of samples with λ > 0
  double energy_ratio;      ///< energy at the last sample / initial energy
  /// With a far wall (RodScene::far_gap): maximal runs of samples with λ_0 > 0 at it; the
  /// number of impacts; and the largest penetration of either wall over the samples [mm]
  /// (RunSummary::max_penetration). NaN without a far wall: not applicable.
  /// Impacts are the alternations of the wall that alone pushes the rod: the samples where
  /// exactly one wall pushes, grouped into maximal runs of the same wall, whatever lies between
  /// (chatter within one impact, a flight, samples where both walls push, is not a new impact).
  /// A sample where both walls push changes nothing, except that a run whose first contact is at
  /// both walls at once counts that as its first impact. The exact solution has one impact per
  /// contact, at alternating walls.
  double far_contact_episodes;
  double impacts;
  double max_penetration;
};

Indicators evaluate_indicators(const RodScene& scene, const ContactTrace& trace,
                               const RunSummary& summary, const IndicatorOptions& options);

/// The indicators of several runs of one scene (a sweep's batch), each the same, bit for bit,
/// as evaluate_indicators of that run alone: the exact solution at the samples is evaluated
/// once for all of them (BM_IndicatorsOfABatch against BM_Indicators measures what that saves).
/// The spans are parallel, one entry per run.
void evaluate_indicators(const RodScene& scene, std::span<const ContactTrace* const> traces,
                         std::span<const RunSummary> summaries,
                         std::span<const IndicatorOptions> options, std::span<Indicators> out);

/// One contact's indicators in a scene of bodies (core/model/scene.hpp): the paper's indicators at
/// that contact, against the exact reference. All NaN when the run is not ok.
struct ContactIndicators {
  double eps_p;             ///< eq. 18 for the contact's pressure
  double eps_v;             ///< eq. 18 for its node's velocity
  double nop_p;             ///< peaks of the pressure
  double nop_v;             ///< peaks of the velocity
  double p_max;             ///< largest sampled pressure [MPa]
  double p_max_ratio;       ///< p_max / (ρ·c·V) of the contact's segment, V the largest |v0|
  double contact_episodes;  ///< maximal runs of samples with λ > 0
};

/// The indicators of a run of a scene of bodies (simulate(AssembledScene)) against `reference`,
/// the scene's reference at the run's samples (core/reference/scene_reference.hpp: the exact
/// solution, or a converged one): every contact's into `contacts` (one per contact,
/// scene_contacts() order), and the primary contact's returned as Indicators (energy_ratio and
/// max_penetration, the largest violation of any constraint, as for the rod; far_contact_episodes
/// and impacts NaN: they describe the rod's two walls). Peak prominences are fractions of ρ·c·V for
/// the pressure of a contact (its segment's ρ·c) and of V for the velocity, with V the largest
/// initial |velocity| of a body.
Indicators evaluate_indicators(const Scene& scene, const SceneReference& reference,
                               const ContactTrace& trace, const RunSummary& summary,
                               const IndicatorOptions& options,
                               std::span<ContactIndicators> contacts);

/// The pressure scale of a contact of a scene of bodies (one of scene_contacts()): ρ·c of the
/// contact's segment times `velocity_scale`, the largest initial |velocity| of a body
/// (SceneDerived::velocity_scale): the scale of its peak prominence and p_max_ratio.
double contact_pressure_scale(const Scene& scene, const SceneContact& contact,
                              double velocity_scale);

/// The same for a user's model (core/model/model_scene.hpp) against its reference samples
/// (core/reference/model_reference.hpp; a contact without samples gets NaN), `primary` the primary
/// contact's index. A model knows no ρ·c: a contact's pressure scale (peak prominence, p_max_ratio)
/// is the largest |pressure| of its reference, its velocity scale the largest |velocity| of its
/// reference (for the paper's rod with the exact solution as reference: ρ·c·v0 and v0, as above).
Indicators evaluate_indicators(const std::vector<ContactSamples>& reference, int primary,
                               const ContactTrace& trace, const RunSummary& summary,
                               const IndicatorOptions& options,
                               std::span<ContactIndicators> contacts);

}  // namespace impactid

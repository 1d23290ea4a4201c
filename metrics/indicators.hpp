// The indicators of one run, compared with the exact solution at the samples t_i = i·Δt,
// i = 1..N (see RodImpactExact::at_sample for the convention on jumps).
#pragma once

#include "core/rod_scene.hpp"
#include "core/simulation.hpp"

namespace impactid {

struct IndicatorOptions {
  /// Minimum prominence of a counted peak, as a fraction of ρ·c·v0 (pressure) and of |v0|
  /// (velocity). See peak_count.hpp for the rule and why. > 0.
  double peak_prominence = 1e-6;
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
};

Indicators evaluate_indicators(const RodScene& scene, const ContactTrace& trace,
                               const RunSummary& summary, const IndicatorOptions& options);

}  // namespace impactid

#include "metrics/indicators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/exact_solution.hpp"
#include "metrics/peak_count.hpp"
#include "metrics/relative_error.hpp"

namespace impactid {

Indicators evaluate_indicators(const RodScene& scene, const ContactTrace& trace,
                               const RunSummary& summary, const IndicatorOptions& options) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (summary.status != RunStatus::ok) return {nan, nan, nan, nan, nan, nan, nan, nan};

  const RodSceneDerived derived = derive(scene);
  const RodImpactExact exact(scene);
  RelativeErrorSum pressure_error, velocity_error;
  double p_max = -std::numeric_limits<double>::infinity();
  long episodes = 0;
  bool in_contact = false;
  for (long i = 0; i < trace.size(); ++i) {
    const ContactNodeValues e = exact.at_sample(i + 1);
    pressure_error.add(e.pressure, trace.pressure[i]);
    velocity_error.add(e.velocity, trace.velocity[i]);
    p_max = std::max(p_max, trace.pressure[i]);
    const bool active = trace.pressure[i] > 0.0;
    if (active && !in_contact) ++episodes;
    in_contact = active;
  }
  Indicators out;
  out.eps_p = pressure_error.value();
  out.eps_v = velocity_error.value();
  out.nop_p = static_cast<double>(
      count_peaks(trace.pressure, options.peak_prominence * derived.pressure_scale));
  out.nop_v = static_cast<double>(
      count_peaks(trace.velocity, options.peak_prominence * std::abs(scene.velocity)));
  out.p_max = p_max;
  out.p_max_ratio = derived.pressure_scale > 0.0 ? p_max / derived.pressure_scale : nan;
  out.contact_episodes = static_cast<double>(episodes);
  out.energy_ratio =
      summary.initial_energy > 0.0 ? summary.final_energy / summary.initial_energy : nan;
  return out;
}

}  // namespace impactid

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
  if (summary.status != RunStatus::ok) return {nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan};

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
  out.far_contact_episodes = nan;
  out.impacts = nan;
  out.max_penetration = nan;
  if (scene.far_gap) {
    // The wall that alone held the rod last. A sample where both walls push is a hand-over (or a
    // rod pressed between them): it does not change `last`, so it never counts an impact, except
    // when it is the first contact of the run (`both`: one impact, continued by either wall).
    enum class Wall { none, main, far, both } last = Wall::none;
    long far_episodes = 0, impacts = 0;
    bool far_in_contact = false;
    for (long i = 0; i < trace.size(); ++i) {
      const bool main_active = trace.pressure[i] > 0.0;
      const bool far_active = trace.far_pressure[i] > 0.0;
      if (far_active && !far_in_contact) ++far_episodes;
      far_in_contact = far_active;
      if (main_active && far_active) {
        if (last == Wall::none) {
          ++impacts;
          last = Wall::both;
        }
      } else if (main_active || far_active) {
        const Wall wall = main_active ? Wall::main : Wall::far;
        if (last != wall && last != Wall::both) ++impacts;
        last = wall;
      }
    }
    out.far_contact_episodes = static_cast<double>(far_episodes);
    out.impacts = static_cast<double>(impacts);
    out.max_penetration = summary.max_penetration;
  }
  return out;
}

}  // namespace impactid

#include "study/studies/spectral_report.hpp"

#include <stdexcept>

#include "core/methods/method_registry.hpp"
#include "study/studies/spectral_study.hpp"

namespace impactid {

SpectralReport spectral_report(const Simulation& simulation, std::optional<double> omega_max,
                               bool scene_given, std::span<const double> omega_dt) {
  SpectralReport r{.simulation = simulation};
  if (omega_max) {
    r.omega_max = *omega_max;
    r.omega_max_from = "omega-max";
  } else if (scene_given) {
    // The highest mode of the rod at this Courant number (core/spectral/amplification.hpp).
    const RodScene* rod = simulation.rod();
    if (!rod) throw std::invalid_argument("a method's spectral report takes Ω_max from the rod");
    r.omega_max = rod_max_omega_dt(rod->mass, rod->courant);
    r.omega_max_from = "courant";
  }
  const MethodParams& params = simulation.method;
  r.rho_inf = high_frequency_spectral_radius(params);
  r.period_error_coefficient = period_error_coefficient(params);
  r.max_rho = stability_scan_max_rho(params, r.omega_max);
  r.stable = is_stable(params, r.omega_max);
  // The δ that minimises the period error is HHT's (independent α and δ): reported for the
  // method whose parameters include α.
  if (method_takes(descriptor(params), "alpha")) {
    r.alpha = reported_value(params, "alpha");
    r.delta_min_limit = hht_delta_minimizing_period_error(*r.alpha, std::nullopt);
  }
  for (const double w : omega_dt) {
    SpectralAtOmega a{w, spectral_properties(params, w)};
    if (r.alpha) a.delta_min = hht_delta_minimizing_period_error(*r.alpha, w);
    r.at.push_back(a);
  }
  return r;
}

}  // namespace impactid

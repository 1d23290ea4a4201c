// One method's spectral analysis on the undamped oscillator ü + ω²u = 0
// (core/spectral/amplification.hpp), as `impactid spectral` prints it and `impactid.spectral()`
// returns it (python/): ρ∞, the Ω → 0 period-error coefficient, stability up to Ω_max, ρ, ξ̄ and the
// period error at given Ω = ω·Δt, and for HHT the δ that minimises the period error at its α.
#pragma once

#include <cmath>
#include <optional>
#include <span>
#include <vector>

#include "core/spectral/amplification.hpp"
#include "study/plan/simulation_settings.hpp"

namespace impactid {

/// Ω_max of the stability scan when neither omega_max nor courant/mass is given: the default of
/// is_stable(), far above any mode a time step resolves ("unconditionally stable").
inline constexpr double kDefaultSpectralOmegaMax = 1e4;

struct SpectralAtOmega {
  double omega_dt;
  SpectralProperties properties;
  double delta_min = NAN;  ///< HHT only
};

struct SpectralReport {
  Simulation simulation;
  double rho_inf = 0.0, period_error_coefficient = 0.0;
  double omega_max = kDefaultSpectralOmegaMax;
  const char* omega_max_from = "default";  ///< "default", "courant" or "omega-max"
  double max_rho = 0.0;
  bool stable = false;
  std::optional<double> alpha;  ///< HHT: its α, for δ_min
  double delta_min_limit = NAN;
  std::vector<SpectralAtOmega> at;
};

/// The report of the simulation's method. Ω_max: `omega_max` when given (> 0, finite: the
/// caller checks, and that it is not given with courant or mass), else the rod's highest mode
/// at its Courant number and mass when `scene_given` (courant or mass was given), else the
/// default; `scene_given` needs the simulation's scene to be the rod (std::invalid_argument
/// otherwise). `omega_dt`: each > 0 and finite (checked by the caller).
SpectralReport spectral_report(const Simulation& simulation, std::optional<double> omega_max,
                               bool scene_given, std::span<const double> omega_dt);

}  // namespace impactid

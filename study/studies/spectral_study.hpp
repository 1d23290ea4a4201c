// A spectral study (`kind = "spectral"` in a plan): the amplification-matrix properties of
// several methods as curves over Ω = ω·Δt — spectral radius ρ, algorithmic damping ratio ξ̄,
// relative period error — with ρ∞ and the Ω → 0 period-error coefficient per method, the HHT δ
// that minimises the period error as a function of α (the check behind the paper's eq. 19,
// δ = −1.5α; Serfőző & Pere 2022, sec. 4.2, doi:10.1556/606.2022.00599), and the HHT stability
// map over (α, δ). Every number comes from core/spectral/amplification.hpp; this module only lays
// out the computation and the file.
//
// The file (format "impactid-spectral-1") is documented in results/README.md; the figure
// scripts rely on its dataset names.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "study/plan/plan.hpp"

namespace impactid {

/// Root attribute `format` of a spectral results file.
inline constexpr const char* kSpectralFormat = "impactid-spectral-1";

struct SpectralResults {
  // Provenance, as in a study's results file.
  std::string plan_name, plan_text, impactid_version, git_revision, date;
  long threads = 1;
  double wall_time_s = 0.0;

  std::vector<double> omega_dt;           ///< [K]
  std::vector<std::string> method_label;  ///< [M], SpectralMethod::label
  std::vector<std::string> method_name;   ///< [M], "newmark", "hht", … (to_string(MethodKind))
  /// [M × K], row-major (method, omega_dt). ξ̄ and the period error are NaN where the principal
  /// pair is not oscillatory.
  std::vector<double> spectral_radius, damping_ratio, period_error;
  std::vector<double> rho_inf;                   ///< [M]; +inf for central difference
  std::vector<double> period_error_coefficient;  ///< [M]

  std::vector<double> alpha, delta;  ///< [A], [D]
  /// [A]: hht_delta_minimizing_period_error(α, Ω → 0) and (α, omega_dt_reference).
  std::vector<double> delta_min_period_error_limit, delta_min_period_error;
  std::vector<int> stable;                  ///< [A × D] (alpha, delta): 1 stable, 0 not
  std::vector<double> max_spectral_radius;  ///< [A × D]: max ρ over the stability scan
  double omega_dt_reference = 1.0;
  double stability_omega_max = 1e4;
};

/// Computes everything with `threads` OpenMP threads (>= 1); the numbers do not depend on it.
/// Provenance fields are left for the caller.
SpectralResults compute_spectral_study(const SpectralStudy& study, int threads);

/// Number of spectral evaluations compute_spectral_study() makes for the stability map, for a
/// --dry-run estimate: A × D × the samples of one stability scan.
long stability_map_evaluations(const SpectralStudy& study);

/// Max ρ over the Ω samples is_stable() scans (core/spectral/amplification.hpp: from
/// kStabilityScanMinOmega to omega_max, kStabilityScanSamplesPerDecade per decade), for any
/// method; NaN for invalid input.
double stability_scan_max_rho(const MethodParams& params, double omega_max);

/// Writes the file atomically (Hdf5Writer). Throws Hdf5Error naming the file, also for arrays
/// whose sizes do not match.
void write_spectral_results(const std::filesystem::path& path, const SpectralResults& results);

/// True if `path` is an HDF5 file whose root attribute `format` is kSpectralFormat; false for a
/// missing, foreign or unreadable file. Never throws.
bool is_spectral_results_file(const std::filesystem::path& path);

}  // namespace impactid

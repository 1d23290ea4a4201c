// Matching algorithmic damping across methods: the parameter of a one-parameter method family
// that gives a required algorithmic damping ratio ξ̄ at one Ω = ω·Δt. This is how impactid
// makes the paper's comparison "by identical dissipation" (Serfőző & Pere 2022, sec. 5,
// doi:10.1556/606.2022.00599) precise: equal ξ̄ at the Ω of the mesh's highest mode
// (rod_max_omega_dt), the mode whose spurious oscillation the damping is there to remove.
//
// ξ̄ comes from spectral_properties() (core/spectral/amplification.hpp); this module only searches.
// Pure functions, thread-safe; nothing throws.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "core/methods/method.hpp"

namespace impactid {

/// A one-parameter family with adjustable dissipation: its place in damping_families(). The
/// families are the registered methods' (MethodDescriptor::damping_families), in registry order:
/// newmark (δ), hht-eq19 (α, δ = −1.5α), hht-eq15 (α, δ = −α), generalized-alpha (ρ∞),
/// rho-bathe (ρ∞ at γ₀(ρ∞)), wilson-theta (θ), noh-bathe (p), kim-explicit (p), kr-alpha (ρ∞).
enum class DampingFamily : std::size_t {};

struct DampingFamilyInfo {
  DampingFamily family;
  const char* name;   ///< "newmark", "hht-eq19", "hht-eq15", "generalized-alpha", …
  const char* label;  ///< for tables: "hht (delta = -1.5*alpha)"
  const char*
      parameter;  ///< the plan/CLI name of the varied parameter: "delta", "alpha", "rho_inf", …
  /// The searched range, from the end without algorithmic damping (ξ̄ = 0: δ = 0, α = 0,
  /// ρ∞ = 1) to the most dissipative end. Newmark's δ has no upper bound; 2 reaches twice the
  /// damping of backward Euler (δ = 1 has exactly backward Euler's ξ̄).
  double undamped_end, damped_end;
};

/// The families, in registry order.
std::span<const DampingFamilyInfo> damping_families();
const DampingFamilyInfo& family_info(DampingFamily family);
/// The family named `name` ("hht-eq15"); nullopt if no method registers it.
std::optional<DampingFamily> find_damping_family(std::string_view name);

/// The method of a family at its parameter value (hht_eq19: α and δ = −1.5α; hht_eq15: α and
/// δ unset, i.e. −α).
MethodParams family_params(DampingFamily family, double parameter);

/// The method a family belongs to, by its plan name ("hht" for both HHT families).
const char* family_method(DampingFamily family);
/// The family's parameters at a value of its varied parameter, by their plan names (hht_eq19:
/// alpha and delta = -1.5*alpha), as `impactid spectral --match-damping` reports them.
std::vector<std::pair<const char*, double>> family_parameters(DampingFamily family,
                                                              double parameter);

/// The methods without a damping parameter (no damping family), whose fixed ξ̄(Ω) a match is
/// reported beside, by name, in registry order: cdm, backward-euler, bathe, tr-bdf2, houbolt.
std::span<const std::pair<const char*, MethodParams>> fixed_damping_methods();

struct DampingMatch {
  DampingFamily family{};
  bool reachable = false;
  /// The matched parameter (NaN when not reachable) and the ξ̄ it gives.
  double parameter = 0.0, damping_ratio = 0.0;
  /// Smallest and largest ξ̄ over the scan of the family's range (NaN if no sample is
  /// oscillatory): what a target outside them would need.
  double attainable_min = 0.0, attainable_max = 0.0;
  /// Number of brackets found by the scan. ξ̄ need not be monotone in the parameter (HHT with
  /// δ = −α peaks near α = −1/3); with more than one root, the one nearest the undamped end
  /// is returned.
  int roots = 0;
};

/// Samples of the scan that brackets the roots (evenly spaced over the family's range).
inline constexpr int kDampingScanIntervals = 400;

/// The parameter whose ξ̄ at Ω = omega_dt equals target_damping_ratio: a scan of
/// kDampingScanIntervals + 1 values from the undamped end brackets the first sign change of
/// ξ̄ − target (non-oscillatory samples, ξ̄ = NaN, break brackets), which bisection then narrows
/// to adjacent doubles. Not reachable (reachable = false, parameter NaN) if no sample brackets
/// the target, or for omega_dt not finite and > 0 or a target not finite.
DampingMatch match_damping(DampingFamily family, double omega_dt, double target_damping_ratio);

}  // namespace impactid

// `impactid spectral`: the spectral analysis of one method on the undamped oscillator
// (core/spectral/amplification.hpp) — ρ∞, the Ω → 0 period-error coefficient, stability up to
// Ω_max, and ρ, ξ̄ and the period error at given Ω = ω·Δt (--omega-dt); for HHT also the δ that
// minimises the period error at its α. Text or --json.
//
// `impactid spectral --match-damping XI --omega-dt W`: for each one-parameter family of
// study/studies/damping_match.hpp, the parameter whose algorithmic damping ratio at Ω = W is XI,
// and the fixed ξ̄(W) of backward Euler and central difference.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace impactid {

std::function<int()> add_spectral_command(CLI::App& app);

}  // namespace impactid

// The largest step an explicit method may take on a system with a diagonal (lumped) mass: a bound
// on the highest natural frequency ω_max of M·ü + K·u = 0 from Gershgorin's theorem applied to
// the rows of M⁻¹·K, whose eigenvalues are the ω²:
//   ω_max² <= max_i Σ_j |K_ij| / M_ii.
// The bound holds on every mesh, so a step within 2/ω_bound is certainly within central
// difference's limit Δt·ω_max <= 2. It is exact for a uniform lumped rod (every row gives
// 4·E/(ρ·h²) = (2c/h)², the free-free chain's highest mode, the half-mass end rows included), so
// there the limit is Courant 1, the magic time step; on graded meshes and at the junctions of
// segments it is conservative. (Gershgorin on the symmetric M^(−1/2)·K·M^(−1/2) is not tight on the
// rod: the rows beside a half-mass end give 1.10·(2c/h)².) Damping is left out: it shortens
// central difference's limit (Δt·ω <= 2(√(1+ξ²) − ξ)), which this bound does not see.
//
// Thread safety: free functions of values.
#pragma once

#include "core/contact/contact_treatment.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

/// The Gershgorin bound on ω_max² above [1/s²]; +inf when the mass is not diagonal or has a
/// non-positive entry (no explicit limit can be certified then).
double highest_frequency_squared_bound(const SecondOrderSystem& system);
double highest_frequency_squared_bound(const SparseSystem& system);
/// The same bound with the penalty law's springs (core/contact/contact_treatment.hpp) added to K: a
/// spring k on a wall's dof adds k to its row sum, one between two dofs 2·k to each. Other laws
/// add nothing (their forces are implicit).
double highest_frequency_squared_bound(const SecondOrderSystem& system,
                                       const ContactPenalties& contact);
double highest_frequency_squared_bound(const SparseSystem& system, const ContactPenalties& contact);

/// Whether Δt·ω_bound <= 2 up to round-off (relative 1e-12 on Δt²·ω², so that Courant 1 computed
/// as h/c counts as within): an explicit step that certainly does not excite a growing mode.
bool within_explicit_limit(double dt, double frequency_squared_bound);

}  // namespace impactid

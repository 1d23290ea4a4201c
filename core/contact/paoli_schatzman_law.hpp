// Paoli & Schatzman's impact law (Paoli & Schatzman 2002, SIAM J. Numer. Anal. 40(2):702–733;
// Siconos's SchatzmanPaoliOSI): central difference's forward increment with the gap held on the
// weighted mean (u_{n+1} + e·u_{n−1})/(1 + e) rather than on u_{n+1}, e Newton's coefficient of
// restitution. For a constraint g(u) = G·u − gap <= 0,
//   g((u₊ + e·u₋)/(1 + e)) <= 0  ⇔  G·u₊ <= gap − e·g(u₋),
// Lagrange's condition on u₊ with the gap shifted by −e·g(u₋), the violation of the previous
// displacement. So the law is Lagrange's multiplier with that shift: the same Delassus matrix, the
// same complementarity problem, each pushed DOF snapped onto its shifted wall; λ >= 0, and the
// weighted mean's gap holds exactly where λ > 0. A mass that hits the wall at speed v leaves it at
// about e·v over the two steps around the impact; e = 0 is Lagrange's law bit for bit.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/model/second_order_system.hpp"

namespace impactid {

/// The shift of one gap, −e·g(u₋), from the violation g(u₋) of the previous displacement.
inline double restitution_gap_shift(double restitution, double previous_violation) {
  return -restitution * previous_violation;
}

/// Each listed constraint's shift −e·g_j(u₋) into `shifts` (m entries; no allocation).
void restitution_gap_shifts(const std::vector<Constraint>& constraints,
                            const Eigen::VectorXd& u_previous, double restitution,
                            Eigen::VectorXd& shifts);

}  // namespace impactid

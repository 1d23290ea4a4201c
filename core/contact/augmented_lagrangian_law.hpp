// The augmented Lagrangian's own arithmetic: Uzawa's iterations, which every family of steppers
// reaches through the laws' solves (core/contact/contact_treatment.hpp for one wall and two walls,
// core/contact/constraint_list_law.hpp for a constraint list). Its descriptor, parameters and
// checks are in augmented_lagrangian_law.cpp.
//
// Thread safety: a pure function template.
#pragma once

#include <algorithm>

namespace impactid {

/// Iterations of one step's contact solve (augmented-lagrangian; 0 for the others).
struct ContactIterations {
  int iterations = 0;
  bool converged = true;
};

/// Uzawa's iterations (augmented-lagrangian) on a problem of m contacts: `solve_penalized(shift,
/// mu)` must write to mu the solution of the penalty problem whose contact-free penetrations are
/// p + shift (shift_k = μ_j,k·compliance_k), `penetration(mu, k)` the penetration g_k that mu
/// leaves. They stop once the largest penetration is at most `tolerance`·`largest_free`, or after
/// `max_iterations` (ContactTreatment's augmented_tolerance, augmented_max_iterations). `mu` holds
/// the last iterate; `shift` (m entries) is scratch. No allocation.
template <class SolvePenalized, class Penetration>
ContactIterations augmented_lagrangian(int m, const double* compliance, double largest_free,
                                       double tolerance, int max_iterations, double* mu,
                                       double* shift, SolvePenalized&& solve_penalized,
                                       Penetration&& penetration) {
  ContactIterations out;
  for (int k = 0; k < m; ++k) shift[k] = 0.0;
  const double bound = tolerance * largest_free;
  for (out.iterations = 1;; ++out.iterations) {
    solve_penalized(shift, mu);
    double worst = 0.0;
    for (int k = 0; k < m; ++k) worst = std::max(worst, penetration(mu, k));
    if (worst <= bound) return out;
    if (out.iterations == max_iterations) {
      out.converged = false;
      return out;
    }
    for (int k = 0; k < m; ++k) shift[k] = mu[k] * compliance[k];
  }
}

}  // namespace impactid

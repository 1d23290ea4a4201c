#include "core/contact/contact_treatment.hpp"

#include <cmath>
#include <limits>

namespace impactid {

namespace {

// The law and its numbers, with the springs of a constraint list; `k(dof)` is K's diagonal entry.
template <class Diagonal>
ContactPenalties resolve_listed(const ContactTreatment& t,
                                const std::vector<Constraint>& constraints, Diagonal&& k) {
  ContactPenalties out;
  out.law = t.law;
  out.tolerance = t.augmented_tolerance;
  out.max_iterations = t.augmented_max_iterations;
  if (t.law == ContactLaw::paoli_schatzman) {  // Lagrange's multiplier on shifted gaps
    out.law = ContactLaw::lagrange;
    out.restitution = t.restitution;
  }
  if (out.law == ContactLaw::lagrange) return out;
  out.listed.reserve(constraints.size());
  for (const Constraint& c : constraints) {
    double smaller = std::numeric_limits<double>::infinity();
    if (c.plus >= 0) smaller = std::min(smaller, k(c.plus));
    if (c.minus >= 0) smaller = std::min(smaller, k(c.minus));
    out.listed.push_back(penalty_stiffness(t, smaller));
  }
  return out;
}

}  // namespace

ContactPenalties resolve_contact(const ContactTreatment& t, const SecondOrderSystem& system) {
  const Eigen::VectorXd& k = system.stiffness.diag;
  ContactPenalties out =
      resolve_listed(t, system.constraints, [&](Eigen::Index dof) { return k[dof]; });
  if (out.lagrange()) return out;
  out.main = penalty_stiffness(t, k[system.contact_dof]);
  out.far = penalty_stiffness(t, k[system.far_contact_dof]);
  return out;
}

ContactPenalties resolve_contact(const ContactTreatment& t, const SparseSystem& system) {
  return resolve_listed(t, system.constraints,
                        [&](Eigen::Index dof) { return system.stiffness.coeff(dof, dof); });
}

double single_contact_force(double p, double d, double compliance,
                            const ContactPenalties& penalties, ContactIterations& iterations) {
  if (penalties.law != ContactLaw::augmented_lagrangian) return p / (d + compliance);
  double mu = 0.0, shift = 0.0;
  iterations = augmented_lagrangian(
      1, &compliance, p, penalties.tolerance, penalties.max_iterations, &mu, &shift,
      [&](const double* s, double* out) { out[0] = (p + s[0]) / (d + compliance); },
      [&](const double* out, int) { return p - d * out[0]; });
  return mu;
}

double massless_contact_force(double p, double stiffness, double spring,
                              const ContactPenalties& penalties, ContactIterations& iterations) {
  if (penalties.lagrange()) return stiffness * p;
  return single_contact_force(p, 1.0 / stiffness, 1.0 / spring, penalties, iterations);
}

TwoWallForces two_wall_contact_forces(double p_main, double p_far, double d_main, double d_far,
                                      double c_main_far, double c_far_main, double main_compliance,
                                      double far_compliance, const ContactPenalties& penalties,
                                      ContactIterations& iterations) {
  const double dm = d_main + main_compliance, df = d_far + far_compliance;
  if (penalties.law != ContactLaw::augmented_lagrangian || !(std::max(p_main, p_far) > 0.0)) {
    return solve_two_wall_contact(p_main, p_far, dm, df, c_main_far, c_far_main);
  }
  const double compliance[2] = {main_compliance, far_compliance};
  double mu[2] = {0.0, 0.0}, shift[2];
  iterations = augmented_lagrangian(
      2, compliance, std::max(p_main, p_far), penalties.tolerance, penalties.max_iterations, mu,
      shift,
      [&](const double* sh, double* out) {
        const TwoWallForces f =
            solve_two_wall_contact(p_main + sh[0], p_far + sh[1], dm, df, c_main_far, c_far_main);
        out[0] = f.main;
        out[1] = f.far;
      },
      [&](const double* out, int j) {
        return j == 0 ? p_main - d_main * out[0] + c_main_far * out[1]
                      : p_far - d_far * out[1] + c_far_main * out[0];
      });
  return {mu[0], mu[1]};
}

}  // namespace impactid

#include "core/contact/stable_step.hpp"

#include <cmath>
#include <limits>

namespace impactid {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// A listed constraint's spring k adds k to its wall's dof's row sum, or 2·k to each of a pair's
// (|+k| on the diagonal and |−k| off it).
void add_springs(const std::vector<Constraint>& constraints, const std::vector<double>& springs,
                 Eigen::VectorXd& rows) {
  for (std::size_t j = 0; j < constraints.size(); ++j) {
    const Constraint& c = constraints[j];
    const double per_dof = (c.plus >= 0 && c.minus >= 0 ? 2.0 : 1.0) * springs[j];
    if (c.plus >= 0) rows[c.plus] += per_dof;
    if (c.minus >= 0) rows[c.minus] += per_dof;
  }
}
}  // namespace

double highest_frequency_squared_bound(const SecondOrderSystem& system) {
  return highest_frequency_squared_bound(system, ContactPenalties{});
}

double highest_frequency_squared_bound(const SecondOrderSystem& system,
                                       const ContactPenalties& contact) {
  if (!system.mass.is_diagonal()) return kInf;
  const Eigen::Index n = system.size();
  const Tridiagonal& m = system.mass;
  const Tridiagonal& k = system.stiffness;
  Eigen::VectorXd springs = Eigen::VectorXd::Zero(n);
  if (contact.law == ContactLaw::penalty) {
    if (system.has_constraint_list()) {
      add_springs(system.constraints, contact.listed, springs);
    } else {
      if (system.has_contact()) springs[system.contact_dof] += contact.main;
      if (system.has_far_contact()) springs[system.far_contact_dof] += contact.far;
    }
  }
  double bound = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    // A massless contact DOF (a modified mass) is solved from its static equation within the step
    // (core/methods/central_difference.hpp): it has no frequency of its own, and condensing it
    // out only lowers its neighbour's, whose row sum here still counts the coupling to it.
    const bool wall = (system.has_contact() && i == system.contact_dof) ||
                      (system.has_far_contact() && i == system.far_contact_dof);
    if (wall && m.diag[i] == 0.0 && massless(m, i)) continue;
    if (!(m.diag[i] > 0.0)) return kInf;
    double row = std::abs(k.diag[i]) + springs[i];
    if (i > 0) row += std::abs(k.lower[i]);
    if (i + 1 < n) row += std::abs(k.upper[i]);
    bound = std::max(bound, row / m.diag[i]);
  }
  return bound;
}

double highest_frequency_squared_bound(const SparseSystem& system) {
  return highest_frequency_squared_bound(system, ContactPenalties{});
}

double highest_frequency_squared_bound(const SparseSystem& system,
                                       const ContactPenalties& contact) {
  const SparseMatrix& m = system.mass;
  if (!is_diagonal(m)) return kInf;
  const Eigen::VectorXd mass = m.diagonal();
  if (!(mass.minCoeff() > 0.0)) return kInf;
  // Row sums of |K| (K is symmetric, so its columns' sums are its rows').
  Eigen::VectorXd row = Eigen::VectorXd::Zero(mass.size());
  for (Eigen::Index j = 0; j < system.stiffness.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(system.stiffness, j); it; ++it) {
      row[j] += std::abs(it.value());
    }
  }
  if (contact.law == ContactLaw::penalty) {
    add_springs(system.constraints, contact.listed, row);
  }
  return (row.array() / mass.array()).maxCoeff();
}

bool within_explicit_limit(double dt, double frequency_squared_bound) {
  return dt * dt * frequency_squared_bound <= 4.0 * (1.0 + 1e-12);
}

}  // namespace impactid

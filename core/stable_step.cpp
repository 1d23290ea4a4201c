#include "core/stable_step.hpp"

#include <cmath>
#include <limits>

namespace impactid {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

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
      for (std::size_t j = 0; j < system.constraints.size(); ++j) {
        const Constraint& c = system.constraints[j];
        const double per_dof = (c.plus >= 0 && c.minus >= 0 ? 2.0 : 1.0) * contact.listed[j];
        if (c.plus >= 0) springs[c.plus] += per_dof;
        if (c.minus >= 0) springs[c.minus] += per_dof;
      }
    } else {
      if (system.has_contact()) springs[system.contact_dof] += contact.main;
      if (system.has_far_contact()) springs[system.far_contact_dof] += contact.far;
    }
  }
  double bound = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(m.diag[i] > 0.0)) return kInf;
    double row = std::abs(k.diag[i]) + springs[i];
    if (i > 0) row += std::abs(k.lower[i]);
    if (i + 1 < n) row += std::abs(k.upper[i]);
    bound = std::max(bound, row / m.diag[i]);
  }
  return bound;
}

double highest_frequency_squared_bound(const SparseSystem& system) {
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
  return (row.array() / mass.array()).maxCoeff();
}

bool within_explicit_limit(double dt, double frequency_squared_bound) {
  return dt * dt * frequency_squared_bound <= 4.0 * (1.0 + 1e-12);
}

}  // namespace impactid

#include "core/contact/sparse_constraints.hpp"

#include "core/common/parameter_error.hpp"

namespace impactid {

void add_constraint_forces(const std::vector<Constraint>& constraints, const Eigen::VectorXd& f,
                           double s, Eigen::VectorXd& v) {
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const double force = s * f[static_cast<Eigen::Index>(k)];
    if (force == 0.0) continue;
    if (constraints[k].plus >= 0) v[constraints[k].plus] += force;
    if (constraints[k].minus >= 0) v[constraints[k].minus] -= force;
  }
}

double constraint_row(const Constraint& c, const Eigen::VectorXd& x) {
  double g = 0.0;
  if (c.plus >= 0) g += x[c.plus];
  if (c.minus >= 0) g -= x[c.minus];
  return g;
}

Eigen::MatrixXd delassus_matrix(const std::vector<Constraint>& constraints,
                                const SparseFactorization& a, double scale) {
  const auto m = static_cast<Eigen::Index>(constraints.size());
  Eigen::MatrixXd d(m, m);
  Eigen::VectorXd column(a.size()), unit(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    unit.setZero();
    unit[k] = 1.0;
    column.setZero();
    add_constraint_forces(constraints, unit, 1.0, column);
    a.solve_in_place(column);
    for (Eigen::Index j = 0; j < m; ++j) {
      d(j, k) = scale * constraint_row(constraints[static_cast<std::size_t>(j)], column);
    }
  }
  return (0.5 * (d + d.transpose())).eval();
}

std::string pivot_failure(const char* what, const SparseFactorization& f) {
  return std::string(what) + " is not positive definite: pivot " + format_value(f.failed_pivot()) +
         " at DOF " + std::to_string(f.failed_dof());
}

}  // namespace impactid

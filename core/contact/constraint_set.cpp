#include "core/contact/constraint_set.hpp"

namespace impactid {

void set_up_constraints(const SecondOrderSystem& system, const TridiagonalFactorization& a,
                        double scale, Eigen::MatrixXd& influence,
                        std::vector<std::pair<Eigen::Index, Eigen::Index>>& rows,
                        Eigen::MatrixXd& delassus) {
  const Eigen::Index n = system.size();
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  influence.setZero(n, m);
  rows.assign(static_cast<std::size_t>(m), {0, 0});
  delassus.setZero(m, m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const Constraint& c = system.constraints[static_cast<std::size_t>(k)];
    if (c.plus >= 0) influence.col(k) += a.inverse_column(c.plus);
    if (c.minus >= 0) influence.col(k) -= a.inverse_column(c.minus);
    Eigen::Index begin = 0, end = n;
    while (begin < n && influence(begin, k) == 0.0) ++begin;
    while (end > begin && influence(end - 1, k) == 0.0) --end;
    rows[static_cast<std::size_t>(k)] = {begin, end};
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    const Constraint& c = system.constraints[static_cast<std::size_t>(j)];
    for (Eigen::Index k = 0; k < m; ++k) {
      double g = 0.0;
      if (c.plus >= 0) g += influence(c.plus, k);
      if (c.minus >= 0) g -= influence(c.minus, k);
      delassus(j, k) = scale * g;
    }
  }
  // Symmetric in exact arithmetic; made exactly so for the Cholesky of the contact solver.
  delassus = (0.5 * (delassus + delassus.transpose())).eval();
}

void apply_constraint_forces(const Eigen::MatrixXd& influence,
                             const std::vector<std::pair<Eigen::Index, Eigen::Index>>& rows,
                             const Eigen::VectorXd& forces, Eigen::VectorXd& x) {
  for (Eigen::Index k = 0; k < forces.size(); ++k) {
    const double f = forces[k];
    if (f == 0.0) continue;
    const auto [begin, end] = rows[static_cast<std::size_t>(k)];
    const double* column = influence.col(k).data();
    for (Eigen::Index i = begin; i < end; ++i) x[i] -= f * column[i];
  }
}

void snap_walls(const std::vector<Constraint>& constraints, const Eigen::VectorXd& forces,
                Eigen::VectorXd& u) {
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    if (!(forces[static_cast<Eigen::Index>(k)] > 0.0)) continue;
    const Constraint& c = constraints[k];
    if (c.minus < 0) u[c.plus] = c.gap;
    if (c.plus < 0) u[c.minus] = -c.gap;
  }
}

void snap_walls(const std::vector<Constraint>& constraints, const Eigen::VectorXd& forces,
                Eigen::VectorXd& u, const Eigen::VectorXd& gap_offsets) {
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const auto j = static_cast<Eigen::Index>(k);
    if (!(forces[j] > 0.0)) continue;
    const Constraint& c = constraints[k];
    const double gap = c.gap + gap_offsets[j];
    if (c.minus < 0) u[c.plus] = gap;
    if (c.plus < 0) u[c.minus] = -gap;
  }
}

}  // namespace impactid

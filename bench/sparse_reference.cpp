#include "sparse_reference.hpp"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include "core/model/second_order_system.hpp"

namespace impactid {
namespace {

Eigen::SparseMatrix<double> sparse(const Tridiagonal& t, double scale) {
  const Eigen::Index n = t.size();
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index i = 0; i < n; ++i) {
    entries.emplace_back(i, i, scale * t.diag[i]);
    if (i > 0 && t.lower[i] != 0.0) entries.emplace_back(i, i - 1, scale * t.lower[i]);
    if (i + 1 < n && t.upper[i] != 0.0) entries.emplace_back(i, i + 1, scale * t.upper[i]);
  }
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

}  // namespace

std::vector<double> sparse_reference_pressure(const RodScene& scene, const HhtParams& params) {
  const RodSceneDerived d = derive(scene);
  const SecondOrderSystem system = assemble_rod(scene);
  const ImplicitCoefficients c = implicit_coefficients(params);
  const Eigen::Index n = system.size(), contact = system.contact_dof;
  const double dt = d.time_step, dt2 = dt * dt, af = c.alpha_f;

  const Eigen::SparseMatrix<double> mass = sparse(system.mass, 1.0);
  const Eigen::SparseMatrix<double> stiffness = sparse(system.stiffness, 1.0);
  const Eigen::SparseMatrix<double> effective = mass + (1.0 - af) * c.b1 * dt2 * stiffness;
  // Augmented matrix [A e_c; e_c^T 0] for a step in contact (acceleration unknowns and λ).
  Eigen::SparseMatrix<double> augmented(n + 1, n + 1);
  {
    std::vector<Eigen::Triplet<double>> entries;
    for (int k = 0; k < effective.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(effective, k); it; ++it) {
        entries.emplace_back(it.row(), it.col(), it.value());
      }
    }
    entries.emplace_back(contact, n, 1.0);
    entries.emplace_back(n, contact, c.b1 * dt2);
    augmented.setFromTriplets(entries.begin(), entries.end());
  }

  Eigen::VectorXd u = Eigen::VectorXd::Zero(n), v = Eigen::VectorXd::Constant(n, scene.velocity);
  Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
  std::vector<double> pressure;
  pressure.reserve(static_cast<std::size_t>(d.step_count));
  for (long step = 0; step < d.step_count; ++step) {
    const Eigen::VectorXd u_predicted = u + dt * v + dt2 * c.b0 * a;
    const Eigen::VectorXd v_predicted = v + dt * c.g0 * a;
    const Eigen::VectorXd rhs = -(stiffness * ((1.0 - af) * u_predicted + af * u));
    // What a general code does: factorise every step.
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.compute(effective);
    Eigen::VectorXd a_next = lu.solve(rhs);
    double lambda = 0.0;
    if (u_predicted[contact] + c.b1 * dt2 * a_next[contact] > system.gap) {
      Eigen::VectorXd rhs_augmented(n + 1);
      rhs_augmented << rhs, system.gap - u_predicted[contact];
      Eigen::SparseLU<Eigen::SparseMatrix<double>> saddle;
      saddle.compute(augmented);
      const Eigen::VectorXd x = saddle.solve(rhs_augmented);
      a_next = x.head(n);
      lambda = x[n];
    }
    u = u_predicted + c.b1 * dt2 * a_next;
    v = v_predicted + c.g1 * dt * a_next;
    a = a_next;
    pressure.push_back(lambda / scene.area);
  }
  return pressure;
}

}  // namespace impactid

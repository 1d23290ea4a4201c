#include "core/methods/implicit_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/algebra/contact_lcp.hpp"
#include "core/algebra/two_wall_contact.hpp"
#include "core/common/function_versions.hpp"
#include "core/contact/constraint_set.hpp"

namespace impactid {

bool ImplicitIntegrator::initialize(const SecondOrderSystem& system,
                                    const ImplicitCoefficients& coefficients, double dt,
                                    const ContactPenalties& contact) {
  c_ = coefficients;
  dt_ = dt;
  contact_ = contact;
  const double k_weight = (1.0 - c_.alpha_f) * c_.b1 * dt * dt;
  const double c_weight = (1.0 - c_.alpha_f) * c_.g1 * dt;
  Tridiagonal effective = system.mass.combined(1.0 - c_.alpha_m, system.stiffness, k_weight);
  if (system.has_damping()) effective = effective.combined(1.0, system.damping, c_weight);
  if (!factorization_.factor(effective)) return false;

  const Eigen::Index n = system.size();
  contact_influence_ = factorization_.inverse_column(system.contact_dof);
  if (system.has_far_contact()) {
    far_influence_ = factorization_.inverse_column(system.far_contact_dof);
    contact_free_.resize(n);
  } else {
    far_influence_.resize(0);
    contact_free_.resize(0);
  }
  formulas_.resize(n);
  Eigen::MatrixXd delassus;
  set_up_constraints(system, factorization_, c_.b1 * dt * dt, constraint_influence_,
                     constraint_rows_, delassus);
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  list_law_.initialize(contact_, m, PenaltyForm::solved_with_step, c_.contact_weight);
  list_ = list_law_.problem(std::move(delassus));
  forces_.resize(m);
  if (!contact_.lagrange()) {
    // The compliance of the weighted force w·λ: a spring k acting through the weight w.
    const double w = c_.contact_weight;
    main_compliance_ = 1.0 / (w * contact_.main);
    far_compliance_ = 1.0 / (w * contact_.far);
  }
  gap_offsets_.setZero(std::max<Eigen::Index>(m, 2));
  massless_.clear();
  const Tridiagonal& damping = system.damping;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!massless(system.mass, i)) continue;
    const bool damped = damping.diag[i] != 0.0 || (i > 0 && damping.lower[i] != 0.0) ||
                        (i + 1 < n && damping.upper[i] != 0.0);
    if (!damped) massless_.push_back(i);
  }
  massless_u_.assign(massless_.size(), 0.0);
  massless_v_.assign(massless_.size(), 0.0);
  return true;
}

void ImplicitIntegrator::remember_massless(const State& s) {
  for (std::size_t k = 0; k < massless_.size(); ++k) {
    massless_u_[k] = s.u[massless_[k]];
    massless_v_[k] = s.v[massless_[k]];
  }
}

void ImplicitIntegrator::report_massless(State& s) const {
  for (std::size_t k = 0; k < massless_.size(); ++k) {
    const Eigen::Index c = massless_[k];
    const double v = (s.u[c] - massless_u_[k]) / dt_;
    s.a[c] = (v - massless_v_[k]) / dt_;
    s.v[c] = v;
  }
}

void ImplicitIntegrator::predict(const SecondOrderSystem& system, State& s) {
  with_fma_versions([&] {
    formulas_.predict(system, c_, dt_, s);
    Eigen::VectorXd& rhs = formulas_.rhs;
    const Eigen::Index contact = system.contact_dof;
    rhs[contact] -= (1.0 - c_.contact_weight) * s.lambda;
    if (s.far_lambda != 0.0) {
      rhs[system.far_contact_dof] += (1.0 - c_.contact_weight) * s.far_lambda;
    }
    for (std::size_t k = 0; k < system.constraints.size(); ++k) {
      const double force = (1.0 - c_.contact_weight) * s.multipliers[static_cast<Eigen::Index>(k)];
      if (force == 0.0) continue;
      if (system.constraints[k].plus >= 0) rhs[system.constraints[k].plus] -= force;
      if (system.constraints[k].minus >= 0) rhs[system.constraints[k].minus] += force;
    }
    factorization_.forward_in_place(rhs);
  });
}

void ImplicitIntegrator::update(State& s) const {
  with_fma_versions([&] { formulas_.update(c_, dt_, s); });
}

bool ImplicitIntegrator::step(const SecondOrderSystem& system, State& s) {
  if (system.has_constraint_list()) return step_constraints(system, s);
  if (system.has_far_contact()) return step_two_walls(system, s);
  if (!massless_.empty()) remember_massless(s);
  predict(system, s);
  Eigen::VectorXd& rhs = formulas_.rhs;
  const Eigen::VectorXd& u_predicted = formulas_.u_predicted;
  const Eigen::Index n = system.size();
  const double dt = dt_, dt2 = dt * dt;
  const Eigen::Index contact = system.contact_dof;

  const bool contact_is_last = contact == n - 1;
  if (!contact_is_last) factorization_.backward_in_place(rhs);
  const double gap = system.gap + gap_offsets_[0];
  double lambda = 0.0;
  ContactIterations iterations;
  if (system.has_contact()) {
    // With the contact dof last, rhs[contact] is final after the forward sweep.
    const double u_free = std::fma(c_.b1 * dt2, rhs[contact], u_predicted[contact]);
    if (u_free > gap) {
      // Force (w·λ) that moves the contact dof from u_free back onto the wall (Lagrange), or
      // the contact law's.
      const double weighted =
          contact_.lagrange()
              ? (u_free - gap) / (c_.b1 * dt2 * contact_influence_[contact])
              : single_contact_force(u_free - gap, c_.b1 * dt2 * contact_influence_[contact],
                                     main_compliance_, contact_, iterations);
      if (contact_is_last) {
        rhs[contact] -= weighted * contact_influence_[contact];
      } else {
        rhs -= weighted * contact_influence_;
      }
      lambda = weighted / c_.contact_weight;
    }
  }
  if (contact_is_last) factorization_.backward_in_place(rhs);
  update(s);
  // Round-off would leave the node a few ulps off the wall; the constraint is exact.
  if (lambda > 0.0 && contact_.lagrange()) s.u[contact] = gap;
  if (!massless_.empty()) report_massless(s);
  list_law_.count(iterations);
  s.lambda = lambda;
  s.t += dt;
  return lambda > 0.0;
}

bool ImplicitIntegrator::step_two_walls(const SecondOrderSystem& system, State& s) {
  if (!massless_.empty()) remember_massless(s);
  predict(system, s);
  Eigen::VectorXd& rhs = formulas_.rhs;
  const Eigen::VectorXd& u_predicted = formulas_.u_predicted;
  contact_free_ = rhs;  // the same size: no allocation
  factorization_.backward_in_place(contact_free_);
  const Eigen::Index n = system.size();
  const double dt = dt_, dt2 = dt * dt;
  const Eigen::Index contact = system.contact_dof, far = system.far_contact_dof;

  // Penetrations of the contact-free prediction, and what a unit weighted force does to them.
  const double k = c_.b1 * dt2;
  // The free positions as step() forms u_free (fused), so that the far wall idle changes no bit.
  const double gap = system.gap + gap_offsets_[0], far_gap = system.far_gap + gap_offsets_[1];
  const double p_main = std::fma(k, contact_free_[contact], u_predicted[contact]) - gap;
  const double p_far = -far_gap - std::fma(k, contact_free_[far], u_predicted[far]);
  const double d_main = k * contact_influence_[contact], d_far = k * far_influence_[far];
  const double c_main_far = k * far_influence_[contact], c_far_main = k * contact_influence_[far];
  TwoWallForces forces;
  if (contact_.lagrange()) {
    forces = solve_two_wall_contact(p_main, p_far, d_main, d_far, c_main_far, c_far_main);
  } else {
    ContactIterations iterations;
    forces = two_wall_contact_forces(p_main, p_far, d_main, d_far, c_main_far, c_far_main,
                                     main_compliance_, far_compliance_, contact_, iterations);
    list_law_.count(iterations);
  }
  if (forces.far == 0.0 && contact == n - 1) {
    // The far wall idle: step()'s operations exactly, so that a far wall never reached changes
    // no bit of a run.
    if (forces.main > 0.0) rhs[contact] -= forces.main * contact_influence_[contact];
    factorization_.backward_in_place(rhs);
  } else {
    rhs = contact_free_;
    if (forces.main > 0.0) rhs -= forces.main * contact_influence_;
    if (forces.far > 0.0) rhs += forces.far * far_influence_;
  }
  update(s);
  if (forces.main > 0.0 && contact_.lagrange()) s.u[contact] = gap;
  if (forces.far > 0.0 && contact_.lagrange()) s.u[far] = -far_gap;
  if (!massless_.empty()) report_massless(s);
  s.lambda = forces.main / c_.contact_weight;
  s.far_lambda = forces.far / c_.contact_weight;
  s.t += dt;
  return forces.main > 0.0;  // as without a far wall (and as central difference): the main wall
}

bool ImplicitIntegrator::step_constraints(const SecondOrderSystem& system, State& s) {
  if (!massless_.empty()) remember_massless(s);
  predict(system, s);
  Eigen::VectorXd& rhs = formulas_.rhs;
  const Eigen::VectorXd& u_predicted = formulas_.u_predicted;
  factorization_.backward_in_place(rhs);
  const double dt = dt_, k = c_.b1 * dt * dt;
  const auto m = static_cast<int>(system.constraints.size());
  // Violations of the contact-free prediction, with u_free formed as the single wall forms it.
  Eigen::VectorXd& violation = list_law_.violation();
  for (int j = 0; j < m; ++j) {
    const Constraint& con = system.constraints[static_cast<std::size_t>(j)];
    double g = -(con.gap + gap_offsets_[j]);
    if (con.plus >= 0) g += std::fma(k, rhs[con.plus], u_predicted[con.plus]);
    if (con.minus >= 0) g -= std::fma(k, rhs[con.minus], u_predicted[con.minus]);
    violation[j] = g;
  }
  list_law_.solve(list_, forces_);
  apply_constraint_forces(constraint_influence_, constraint_rows_, forces_, rhs);
  update(s);
  bool active = false;
  for (int j = 0; j < m; ++j) {
    const double weighted = forces_[j];
    s.multipliers[j] = weighted / c_.contact_weight;
    active = active || weighted > 0.0;
  }
  if (contact_.lagrange()) snap_walls(system.constraints, forces_, s.u, gap_offsets_);
  if (!massless_.empty()) report_massless(s);
  s.t += dt;
  return active;
}

Eigen::VectorXd consistent_acceleration(const SecondOrderSystem& system, const State& state) {
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(system.size());
  if (system.load.active()) rhs = system.load.force;
  system.stiffness.multiply_add(-1.0, state.u, rhs);
  system.damping.multiply_add(-1.0, state.v, rhs);
  rhs[system.contact_dof] -= state.lambda;
  if (state.far_lambda != 0.0) rhs[system.far_contact_dof] += state.far_lambda;
  for (std::size_t k = 0; k < system.constraints.size(); ++k) {
    if (state.multipliers.size() == 0) break;
    const double force = state.multipliers[static_cast<Eigen::Index>(k)];
    if (system.constraints[k].plus >= 0) rhs[system.constraints[k].plus] -= force;
    if (system.constraints[k].minus >= 0) rhs[system.constraints[k].minus] += force;
  }
  const Eigen::Index n = system.size();
  std::vector<Eigen::Index> massless_dofs;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (massless(system.mass, i)) massless_dofs.push_back(i);
  }
  TridiagonalFactorization mass;
  if (massless_dofs.empty()) {
    if (!mass.factor(system.mass)) return Eigen::VectorXd::Constant(n, NAN);
    mass.solve_in_place(rhs);
    return rhs;
  }
  // A modified mass (core/model/rod_scene.hpp): a massless DOF's row of M is zero and nothing
  // couples it to the others, so a unit pivot there leaves the massive DOFs' solve as it is. Its
  // own acceleration then comes from its static equation K_c·u + (contact force) = 0 differentiated
  // twice in time, the contact force taken as constant: K_c·a = 0, a_c = −Σ_{j≠c} K_cj·a_j / K_cc,
  // the acceleration that keeps it on its static position as its neighbours move.
  Tridiagonal regular = system.mass;
  for (Eigen::Index c : massless_dofs) {
    regular.diag[c] = 1.0;
    rhs[c] = 0.0;
  }
  if (!mass.factor(regular)) return Eigen::VectorXd::Constant(n, NAN);
  mass.solve_in_place(rhs);
  const Tridiagonal& k = system.stiffness;
  for (Eigen::Index c : massless_dofs) {
    double coupled = 0.0;
    if (c > 0) coupled += k.lower[c] * rhs[c - 1];
    if (c + 1 < n) coupled += k.upper[c] * rhs[c + 1];
    rhs[c] = -coupled / k.diag[c];
  }
  return rhs;
}

}  // namespace impactid

#include "core/methods/kr_alpha.hpp"

#include <cassert>
#include <cmath>
#include <utility>

#include "core/algebra/contact_lcp.hpp"
#include "core/algebra/two_wall_contact.hpp"
#include "core/contact/constraint_set.hpp"

namespace impactid {
namespace {

// The rows [begin, end) outside which a column is exactly zero.
std::pair<Eigen::Index, Eigen::Index> non_zero_rows(const Eigen::VectorXd& column) {
  const Eigen::Index n = column.size();
  Eigen::Index begin = 0, end = n;
  while (begin < n && column[begin] == 0.0) ++begin;
  while (end > begin && column[end - 1] == 0.0) --end;
  return {begin, end};
}

}  // namespace

void KrAlphaExplicit::respond(bool start, const Eigen::VectorXd& force, Eigen::VectorXd& a,
                              Eigen::VectorXd& w) const {
  const Recurrence& k = recurrence_;
  w = force;
  if (!start) {
    k.e.solve_in_place(w);  // E⁻¹·f (= D⁻¹·M·E⁻¹·D·M⁻¹·f, the header)
    a.resize(0);            // a step's acceleration follows from w
    return;
  }
  k.d.solve_in_place(w);  // D⁻¹·f
  a = force;
  k.mass.solve_in_place(a);  // M⁻¹·f
}

void KrAlphaExplicit::set_up(const SecondOrderSystem& system, bool start,
                             ContactResponse& response) {
  const Eigen::Index n = system.size();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd force = zero;
  force[system.contact_dof] = 1.0;
  respond(start, force, response.a_main, response.w_main);
  if (system.has_far_contact()) {
    force = zero;
    force[system.far_contact_dof] = 1.0;
    respond(start, force, response.a_far, response.w_far);
  } else {
    response.a_far.resize(0);
    response.w_far.resize(0);
  }
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  response.a_list.setZero(start ? n : 0, m);
  response.w_list.setZero(n, m);
  response.rows_a.assign(static_cast<std::size_t>(m), {0, 0});
  response.rows_w.assign(static_cast<std::size_t>(m), {0, 0});
  Eigen::MatrixXd delassus = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd a, w;
  for (Eigen::Index k = 0; k < m; ++k) {
    const Constraint& c = system.constraints[static_cast<std::size_t>(k)];
    force = zero;
    if (c.plus >= 0) force[c.plus] += 1.0;
    if (c.minus >= 0) force[c.minus] -= 1.0;
    respond(start, force, a, w);
    if (start) response.a_list.col(k) = a;
    response.w_list.col(k) = w;
    if (start) response.rows_a[static_cast<std::size_t>(k)] = non_zero_rows(a);
    response.rows_w[static_cast<std::size_t>(k)] = non_zero_rows(w);
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    const Constraint& c = system.constraints[static_cast<std::size_t>(j)];
    for (Eigen::Index k = 0; k < m; ++k) {
      double g = 0.0;
      if (c.plus >= 0) g += response.w_list(c.plus, k);
      if (c.minus >= 0) g -= response.w_list(c.minus, k);
      delassus(j, k) = response.scale * g;
    }
  }
  if (m > 0) symmetrize_contact_operator(delassus);
  response.list = list_law_.problem(std::move(delassus));
}

void symmetrize_contact_operator(Eigen::MatrixXd& g) {
  // Symmetric in exact arithmetic for every damping (the header): a larger asymmetry than
  // round-off's is a bug (an unsymmetric matrix reached the stepper), not a model to refuse.
  assert((g - g.transpose()).cwiseAbs().maxCoeff() <= 1e-6 * g.cwiseAbs().maxCoeff() &&
         "KR-alpha's contact operator is symmetric for symmetric M, C and K "
         "(core/methods/kr_alpha.hpp)");
  g = (0.5 * (g + g.transpose())).eval();
}

bool KrAlphaExplicit::initialize(const SecondOrderSystem& system,
                                 const KrAlphaCoefficients& coefficients, double dt, State& start,
                                 const ContactPenalties& contact) {
  failure_.clear();
  contact_ = contact;
  // The penalty's springs are solved with the forward increment (the header says why).
  list_law_.initialize(contact_, static_cast<Eigen::Index>(system.constraints.size()),
                       PenaltyForm::solved_with_step);
  Recurrence& k = recurrence_;
  k.c = coefficients;
  k.dt = dt;
  k.scale = dt * dt * (0.5 + k.c.gamma);
  const double c_weight = k.c.gamma * dt, k_weight = k.c.beta * dt * dt;
  k.d_matrix =
      system.mass.combined(1.0, system.damping, c_weight).combined(1.0, system.stiffness, k_weight);
  const Tridiagonal e_matrix =
      system.mass.combined(1.0 - k.c.alpha_m, system.damping, (1.0 - k.c.alpha_f) * c_weight)
          .combined(1.0, system.stiffness, (1.0 - k.c.alpha_f) * k_weight);
  if (!k.mass.factor(system.mass)) {
    failure_ = "singular mass matrix";
    return false;
  }
  if (!k.d.factor(k.d_matrix) || !k.e.factor(e_matrix)) {
    failure_ = "singular matrix M + gamma*dt*C + beta*dt^2*K";
    return false;
  }
  start_response_.scale = 0.5 * dt * dt;  // the start's (below)
  set_up(system, true, start_response_);
  step_response_.scale = k.scale;
  set_up(system, false, step_response_);
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  forces_.resize(m);
  scaled_forces_.resize(m);
  k.resize(system.size());
  // The start (the header): the start's contact moves u₁ by Δt²/2 per unit of α1·a₀.
  k.start(system, start,
          [&](Eigen::VectorXd& next) { enforce(system, start_response_, &start.a, next, start); });
  return true;
}

bool KrAlphaExplicit::enforce(const SecondOrderSystem& system, const ContactResponse& response,
                              Eigen::VectorXd* a, Eigen::VectorXd& next, State& at) {
  Eigen::VectorXd& w = recurrence_.w;  // α1·a: moves with the force
  if (system.has_constraint_list()) {
    const bool pushing =
        list_law_.forward_increment(system.constraints, response.list, next, next, forces_);
    if (a != nullptr) apply_constraint_forces(response.a_list, response.rows_a, forces_, *a);
    apply_constraint_forces(response.w_list, response.rows_w, forces_, w);
    scaled_forces_ = response.scale * forces_;
    apply_constraint_forces(response.w_list, response.rows_w, scaled_forces_, next);
    if (contact_.lagrange()) snap_walls(system.constraints, forces_, next);
    at.multipliers = forces_;  // the same size: no allocation
    at.lambda = 0.0;           // the list's are in multipliers
    return pushing;
  }
  const Eigen::Index contact = system.contact_dof;
  const double s = response.scale;
  if (system.has_far_contact()) {
    const Eigen::Index far = system.far_contact_dof;
    TwoWallForces forces;
    if (contact_.lagrange()) {
      forces = solve_two_wall_contact(next[contact] - system.gap, -system.far_gap - next[far],
                                      s * response.w_main[contact], s * response.w_far[far],
                                      s * response.w_far[contact], s * response.w_main[far]);
    } else {
      ContactIterations iterations;
      forces = two_wall_contact_forces(
          next[contact] - system.gap, -system.far_gap - next[far], s * response.w_main[contact],
          s * response.w_far[far], s * response.w_far[contact], s * response.w_main[far],
          1.0 / contact_.main, 1.0 / contact_.far, contact_, iterations);
      list_law_.count(iterations);
    }
    if (forces.main > 0.0) {
      if (a != nullptr) *a -= forces.main * response.a_main;
      w -= forces.main * response.w_main;
      next -= (s * forces.main) * response.w_main;
    }
    if (forces.far > 0.0) {
      if (a != nullptr) *a += forces.far * response.a_far;
      w += forces.far * response.w_far;
      next += (s * forces.far) * response.w_far;
    }
    if (contact_.lagrange()) {
      if (forces.main > 0.0) next[contact] = system.gap;  // exact, not a few ulps off
      if (forces.far > 0.0) next[far] = -system.far_gap;
    }
    at.lambda = forces.main;
    at.far_lambda = forces.far;
    return forces.main > 0.0 || forces.far > 0.0;
  }
  at.lambda = 0.0;
  if (!system.has_contact() || !(next[contact] > system.gap)) return false;
  double lambda = 0.0;
  if (contact_.lagrange()) {
    lambda = (next[contact] - system.gap) / (s * response.w_main[contact]);
  } else {
    ContactIterations iterations;
    lambda = single_contact_force(next[contact] - system.gap, s * response.w_main[contact],
                                  1.0 / contact_.main, contact_, iterations);
    list_law_.count(iterations);
  }
  if (a != nullptr) *a -= lambda * response.a_main;
  w -= lambda * response.w_main;
  next -= (s * lambda) * response.w_main;
  if (contact_.lagrange()) next[contact] = system.gap;
  at.lambda = lambda;
  return true;
}

bool KrAlphaExplicit::step(const SecondOrderSystem& system, State& state) {
  return recurrence_.step(system, state, [&](Eigen::VectorXd& next) {
    return enforce(system, step_response_, nullptr, next, state);
  });
}

double KrAlphaExplicit::energy(const SecondOrderSystem& system, const State& state) {
  return recurrence_.energy(system, state);
}

}  // namespace impactid

#include "core/methods/sparse_kr_alpha.hpp"

#include <utility>

#include "core/contact/constraint_set.hpp"  // snap_walls
#include "core/contact/sparse_constraints.hpp"
#include "core/methods/kr_alpha.hpp"  // symmetrize_contact_operator

namespace impactid {

void SparseKrAlphaExplicit::respond(bool start, Eigen::VectorXd& a, Eigen::VectorXd& w) const {
  const Recurrence& k = recurrence_;
  w = a;  // the same size: no allocation
  if (!start) {
    k.e.solve_in_place(
        w);  // E⁻¹·f (core/methods/kr_alpha.hpp); a step's acceleration follows from w
    return;
  }
  k.mass.solve_in_place(a);  // M⁻¹·f
  k.d.solve_in_place(w);     // D⁻¹·f
}

void SparseKrAlphaExplicit::set_up(const SparseSystem& system, ContactProblem& problem) {
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  Eigen::MatrixXd g(m, m);
  Eigen::VectorXd unit(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    unit.setZero();
    unit[k] = 1.0;
    response_a_.setZero();
    add_constraint_forces(system.constraints, unit, 1.0, response_a_);
    respond(problem.start, response_a_, response_w_);
    for (Eigen::Index j = 0; j < m; ++j) {
      g(j, k) = problem.scale *
                constraint_row(system.constraints[static_cast<std::size_t>(j)], response_w_);
    }
  }
  if (m > 0) symmetrize_contact_operator(g);
  problem.list = list_law_.problem(std::move(g));
}

bool SparseKrAlphaExplicit::initialize(const SparseSystem& system,
                                       const KrAlphaCoefficients& coefficients, double dt,
                                       State& start, const ContactPenalties& contact) {
  failure_.clear();
  contact_ = contact;
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  list_law_.initialize(contact_, m,
                       PenaltyForm::solved_with_step);  // core/methods/kr_alpha.hpp: why
  Recurrence& k = recurrence_;
  k.c = coefficients;
  k.dt = dt;
  k.scale = dt * dt * (0.5 + k.c.gamma);
  const double c_weight = k.c.gamma * dt, k_weight = k.c.beta * dt * dt;
  k.d_matrix = system.mass + k_weight * system.stiffness;
  SparseMatrix e_matrix =
      (1.0 - k.c.alpha_m) * system.mass + ((1.0 - k.c.alpha_f) * k_weight) * system.stiffness;
  if (system.has_damping()) {
    k.d_matrix += c_weight * system.damping;
    e_matrix += ((1.0 - k.c.alpha_f) * c_weight) * system.damping;
  }
  if (!k.mass.factor(system.mass)) {
    failure_ = pivot_failure("the mass matrix", k.mass);
    return false;
  }
  if (!k.d.factor(k.d_matrix)) {
    failure_ = pivot_failure("the matrix M + gamma*dt*C + beta*dt^2*K", k.d);
    return false;
  }
  if (!k.e.factor(e_matrix)) {
    failure_ =
        pivot_failure("the matrix (1 - alpha_m)*M + (1 - alpha_f)*(gamma*dt*C + beta*dt^2*K)", k.e);
    return false;
  }
  const Eigen::Index n = system.size();
  response_a_.resize(n);
  response_w_.resize(n);
  start_problem_.start = true;
  start_problem_.scale = 0.5 * dt * dt;
  step_problem_.start = false;
  step_problem_.scale = k.scale;
  set_up(system, start_problem_);
  set_up(system, step_problem_);
  forces_.setZero(m);
  lcp_.resize(static_cast<int>(m));
  k.resize(n);
  // The start (core/methods/kr_alpha.hpp): u₁ = u₀ + Δt·v₀ + Δt²/2·α1·a₀, its contact by the
  // start's problem.
  k.start(system, start,
          [&](Eigen::VectorXd& next) { enforce(system, start_problem_, &start.a, next, start); });
  return true;
}

bool SparseKrAlphaExplicit::enforce(const SparseSystem& system, const ContactProblem& problem,
                                    Eigen::VectorXd* a, Eigen::VectorXd& next, State& at) {
  // KrAlphaExplicit's law and order of operations; the correction by one solve (E's; the start's D
  // and M).
  const bool pushing =
      list_law_.forward_increment(system.constraints, problem.list, next, next, forces_, &lcp_);
  at.multipliers = forces_;  // the same size: no allocation
  at.lambda = 0.0;           // the list's are in multipliers
  if (!pushing) return false;
  response_a_.setZero();
  add_constraint_forces(system.constraints, forces_, 1.0, response_a_);
  respond(problem.start, response_a_, response_w_);
  if (a != nullptr) *a -= response_a_;
  recurrence_.w -= response_w_;
  next -= problem.scale * response_w_;
  if (contact_.lagrange()) snap_walls(system.constraints, forces_, next);
  return true;
}

bool SparseKrAlphaExplicit::step(const SparseSystem& system, State& state) {
  return recurrence_.step(system, state, [&](Eigen::VectorXd& next) {
    return enforce(system, step_problem_, nullptr, next, state);
  });
}

double SparseKrAlphaExplicit::energy(const SparseSystem& system, const State& state) {
  return recurrence_.energy(system, state);
}

}  // namespace impactid

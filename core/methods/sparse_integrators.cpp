#include "core/methods/sparse_integrators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/algebra/contact_lcp.hpp"
#include "core/contact/constraint_set.hpp"
#include "core/contact/paoli_schatzman_law.hpp"
#include "core/contact/sparse_constraints.hpp"
#include "core/contact/stable_step.hpp"

namespace impactid {

namespace {

// The contact forces of a step from the free prediction (u at t + Δt without new forces, read
// through `position`): violations, the forces by the law, and the correction A⁻¹·Gᵀ·μ
// subtracted from `x` by one solve. Returns whether a force acts. `gap` gives constraint j's gap
// (shifted or not).
template <class Position, class Gap>
bool contact_forces(const std::vector<Constraint>& constraints, const SparseFactorization& a,
                    Position&& position, Gap&& gap, ConstraintListLaw& law,
                    const ConstraintListProblem& problem, ContactLcpWorkspace& lcp,
                    Eigen::VectorXd& forces, Eigen::VectorXd& correction, Eigen::VectorXd& x) {
  const auto m = static_cast<int>(constraints.size());
  if (m == 0) return false;
  Eigen::VectorXd& violation = law.violation();
  for (int j = 0; j < m; ++j) {
    const Constraint& c = constraints[static_cast<std::size_t>(j)];
    double g = -gap(j);
    if (c.plus >= 0) g += position(c.plus);
    if (c.minus >= 0) g -= position(c.minus);
    violation[j] = g;
  }
  law.solve(problem, forces, &lcp);
  bool active = false;
  for (int j = 0; j < m; ++j) active = active || forces[j] > 0.0;
  if (!active) return false;
  correction.setZero();
  add_constraint_forces(constraints, forces, 1.0, correction);
  a.solve_in_place(correction);
  x -= correction;
  return true;
}

}  // namespace

bool SparseImplicitIntegrator::initialize(const SparseSystem& system,
                                          const ImplicitCoefficients& coefficients, double dt,
                                          const ContactPenalties& contact) {
  c_ = coefficients;
  dt_ = dt;
  failure_.clear();
  contact_ = contact;
  const double k_weight = (1.0 - c_.alpha_f) * c_.b1 * dt * dt;
  const double c_weight = (1.0 - c_.alpha_f) * c_.g1 * dt;
  SparseMatrix effective = (1.0 - c_.alpha_m) * system.mass + k_weight * system.stiffness;
  if (system.has_damping()) effective += c_weight * system.damping;
  if (!factorization_.factor(effective)) {
    failure_ = pivot_failure("the effective matrix", factorization_);
    return false;
  }
  const Eigen::Index n = system.size();
  formulas_.resize(n);
  correction_.resize(n);
  const auto m = static_cast<int>(system.constraints.size());
  list_law_.initialize(contact_, m, PenaltyForm::solved_with_step, c_.contact_weight);
  list_ = list_law_.problem(delassus_matrix(system.constraints, factorization_, c_.b1 * dt * dt));
  forces_.setZero(m);
  gap_offsets_.setZero(m);
  lcp_.resize(m);
  return true;
}

bool SparseImplicitIntegrator::step(const SparseSystem& system, State& s) {
  const double dt = dt_, dt2 = dt * dt;
  // The predictors, α-weighted arguments and update of the tridiagonal integrator, by the same
  // formulas (core/methods/implicit_update.hpp); the previous step's forces and the solve here.
  formulas_.predict(system, c_, dt, s);
  Eigen::VectorXd& rhs = formulas_.rhs;
  const Eigen::VectorXd& u_predicted = formulas_.u_predicted;
  if (s.multipliers.size() > 0) {
    add_constraint_forces(system.constraints, s.multipliers, -(1.0 - c_.contact_weight), rhs);
  }
  factorization_.solve_in_place(rhs);

  const double k = c_.b1 * dt2;
  const bool active = contact_forces(
      system.constraints, factorization_,
      [&](Eigen::Index i) { return std::fma(k, rhs[i], u_predicted[i]); },
      [&](int j) { return system.constraints[static_cast<std::size_t>(j)].gap + gap_offsets_[j]; },
      list_law_, list_, lcp_, forces_, correction_, rhs);
  formulas_.update(c_, dt, s);
  for (Eigen::Index j = 0; j < forces_.size(); ++j) {
    s.multipliers[j] = active ? forces_[j] / c_.contact_weight : 0.0;
  }
  if (active && contact_.lagrange()) snap_walls(system.constraints, forces_, s.u, gap_offsets_);
  s.t += dt;
  return active;
}

bool SparseCentralDifference::initialize(const SparseSystem& system, CdmVelocity velocity,
                                         double dt, const State& initial,
                                         const ContactPenalties& contact) {
  failure_.clear();
  contact_ = contact;
  if (!is_diagonal(system.mass)) {
    failure_ =
        "central difference needs a diagonal (lumped) mass matrix; this model's M has entries off "
        "the diagonal: lump it (row sums) or choose an implicit method";
    return false;
  }
  const double bound = highest_frequency_squared_bound(system, contact);
  within_limit_ = within_explicit_limit(dt, bound);
  stable_step_ = std::isfinite(bound) ? 2.0 / std::sqrt(bound) : 0.0;
  const bool damped = velocity == CdmVelocity::central && system.has_damping();
  SparseMatrix lhs = (1.0 / (dt * dt)) * system.mass;
  if (damped) lhs += (0.5 / dt) * system.damping;
  if (!factorization_.factor(lhs)) {
    failure_ = pivot_failure("the left-hand matrix M/dt^2 + C/(2 dt)", factorization_);
    return false;
  }
  recurrence_.start(velocity, dt, initial);
  recurrence_.one_pass =
      !system.has_damping() && stores_diagonal_only(system.mass) && is_exactly_symmetric(system.stiffness);
  correction_.resize(system.size());
  const auto m = static_cast<int>(system.constraints.size());
  list_law_.initialize(contact_, m, PenaltyForm::explicit_spring);
  list_ = list_law_.problem(delassus_matrix(system.constraints, factorization_, 1.0));
  forces_.setZero(m);
  gap_shifts_.setZero(m);
  lcp_.resize(m);
  return true;
}

bool SparseCentralDifference::step(const SparseSystem& system, State& at_t) {
  recurrence_.predict(system, factorization_);
  Eigen::VectorXd& u_next = recurrence_.u_next;
  // The penalty's violations are those at t (its force is explicit); the others' at t + Δt.
  const Eigen::VectorXd& checked = contact_.explicit_force() ? recurrence_.u : u_next;
  // Paoli–Schatzman's law: each gap shifted by −e·g_j(u₋) (core/contact/paoli_schatzman_law.hpp).
  const bool shifted = contact_.restitution > 0.0;
  if (shifted) {
    restitution_gap_shifts(system.constraints, recurrence_.u_previous, contact_.restitution,
                           gap_shifts_);
  }
  const bool active = contact_forces(
      system.constraints, factorization_, [&](Eigen::Index i) { return checked[i]; },
      [&](int j) {
        const double gap = system.constraints[static_cast<std::size_t>(j)].gap;
        return shifted ? gap + gap_shifts_[j] : gap;
      },
      list_law_, list_, lcp_, forces_, correction_, u_next);
  if (active && shifted) {
    snap_walls(system.constraints, forces_, u_next, gap_shifts_);
  } else if (active && contact_.lagrange()) {
    snap_walls(system.constraints, forces_, u_next);
  }

  for (Eigen::Index j = 0; j < forces_.size(); ++j) at_t.multipliers[j] = active ? forces_[j] : 0.0;
  at_t.lambda = 0.0;
  recurrence_.finish(at_t);
  return active;
}

double SparseCentralDifference::energy(const SparseSystem& system, const State& at_t) {
  if (!within_limit_) return system.energy(at_t.u, at_t.v);
  return recurrence_.energy(system);
}

Eigen::VectorXd consistent_acceleration(const SparseSystem& system, const State& state) {
  const Eigen::Index n = system.size();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  if (system.load.active()) rhs = system.load.force;
  multiply_add(system.stiffness, -1.0, state.u, rhs);
  if (system.has_damping()) multiply_add(system.damping, -1.0, state.v, rhs);
  if (state.multipliers.size() > 0) {
    add_constraint_forces(system.constraints, state.multipliers, -1.0, rhs);
  }
  SparseFactorization mass;
  if (!mass.factor(system.mass)) {
    return Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  }
  mass.solve_in_place(rhs);
  return rhs;
}

}  // namespace impactid

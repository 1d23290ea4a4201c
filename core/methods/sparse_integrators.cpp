#include "core/methods/sparse_integrators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/algebra/contact_lcp.hpp"
#include "core/contact/constraint_set.hpp"
#include "core/contact/sparse_constraints.hpp"
#include "core/contact/stable_step.hpp"
#include "core/methods/central_difference.hpp"

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
  for (Eigen::VectorXd* v :
       {&u_predicted_, &v_predicted_, &u_alpha_, &v_alpha_, &rhs_, &correction_}) {
    v->resize(n);
  }
  const auto m = static_cast<int>(system.constraints.size());
  list_law_.initialize(contact_, m, PenaltyForm::solved_with_step, c_.contact_weight);
  list_ = list_law_.problem(delassus_matrix(system.constraints, factorization_, c_.b1 * dt * dt));
  forces_.setZero(m);
  gap_offsets_.setZero(m);
  lcp_.resize(m);
  return true;
}

bool SparseImplicitIntegrator::step(const SparseSystem& system, State& s) {
  const Eigen::Index n = system.size();
  const double dt = dt_, dt2 = dt * dt;
  const double af = c_.alpha_f;
  // The predictors and α-weighted arguments of the tridiagonal integrator, by the same formulas.
  const double dt2_b0 = dt2 * c_.b0, dt_g0 = dt * c_.g0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double du = std::fma(dt, s.v[i], dt2_b0 * s.a[i]);
    u_predicted_[i] = s.u[i] + du;
    v_predicted_[i] = std::fma(dt_g0, s.a[i], s.v[i]);
    u_alpha_[i] = std::fma(-af, du, u_predicted_[i]);
    v_alpha_[i] = std::fma(-af, dt_g0 * s.a[i], v_predicted_[i]);
  }
  multiply(system.stiffness, u_alpha_, rhs_);
  rhs_ = -rhs_;
  if (system.has_damping()) multiply_add(system.damping, -1.0, v_alpha_, rhs_);
  if (c_.alpha_m != 0.0) multiply_add(system.mass, -c_.alpha_m, s.a, rhs_);
  if (s.multipliers.size() > 0) {
    add_constraint_forces(system.constraints, s.multipliers, -(1.0 - c_.contact_weight), rhs_);
  }
  factorization_.solve_in_place(rhs_);

  const double k = c_.b1 * dt2;
  const bool active = contact_forces(
      system.constraints, factorization_,
      [&](Eigen::Index i) { return std::fma(k, rhs_[i], u_predicted_[i]); },
      [&](int j) { return system.constraints[static_cast<std::size_t>(j)].gap + gap_offsets_[j]; },
      list_law_, list_, lcp_, forces_, correction_, rhs_);
  const double g1_dt = c_.g1 * dt;
  for (Eigen::Index i = 0; i < n; ++i) {
    s.a[i] = rhs_[i];
    s.u[i] = std::fma(k, rhs_[i], u_predicted_[i]);
    s.v[i] = std::fma(g1_dt, rhs_[i], v_predicted_[i]);
  }
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
  velocity_ = velocity;
  dt_ = dt;
  t_ = initial.t;
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
  const Eigen::Index n = system.size();
  u_ = initial.u;
  u_previous_ = initial.u - dt * initial.v + (0.5 * dt * dt) * initial.a;
  u_next_.resize(n);
  scratch_.resize(n);
  correction_.resize(n);
  const auto m = static_cast<int>(system.constraints.size());
  list_law_.initialize(contact_, m, PenaltyForm::explicit_spring);
  list_ = list_law_.problem(delassus_matrix(system.constraints, factorization_, 1.0));
  forces_.setZero(m);
  lcp_.resize(m);
  return true;
}

bool SparseCentralDifference::step(const SparseSystem& system, State& at_t) {
  const Eigen::Index n = system.size();
  const double dt = dt_, inv_dt2 = 1.0 / (dt * dt);
  for (Eigen::Index i = 0; i < n; ++i) scratch_[i] = (2.0 * u_[i] - u_previous_[i]) * inv_dt2;
  multiply(system.mass, scratch_, u_next_);
  multiply_add(system.stiffness, -1.0, u_, u_next_);
  if (system.has_damping()) {
    if (velocity_ == CdmVelocity::central) {
      multiply_add(system.damping, 0.5 / dt, u_previous_, u_next_);
    } else {
      for (Eigen::Index i = 0; i < n; ++i) scratch_[i] = (u_[i] - u_previous_[i]) / dt;
      multiply_add(system.damping, -1.0, scratch_, u_next_);
    }
  }
  factorization_.solve_in_place(u_next_);
  // The penalty's violations are those at t (its force is explicit); the others' at t + Δt.
  const Eigen::VectorXd& checked = contact_.law == ContactLaw::penalty ? u_ : u_next_;
  const bool active = contact_forces(
      system.constraints, factorization_, [&](Eigen::Index i) { return checked[i]; },
      [&](int j) { return system.constraints[static_cast<std::size_t>(j)].gap; }, list_law_, list_,
      lcp_, forces_, correction_, u_next_);
  if (active && contact_.lagrange()) snap_walls(system.constraints, forces_, u_next_);

  at_t.u = u_;
  if (velocity_ == CdmVelocity::central) {
    at_t.v = (u_next_ - u_previous_) / (2.0 * dt);
  } else {
    at_t.v = (u_ - u_previous_) / dt;
  }
  at_t.a = (u_next_ - 2.0 * u_ + u_previous_) * inv_dt2;
  for (Eigen::Index j = 0; j < forces_.size(); ++j) at_t.multipliers[j] = active ? forces_[j] : 0.0;
  at_t.lambda = 0.0;
  at_t.t = t_;
  u_previous_.swap(u_);
  u_.swap(u_next_);
  t_ += dt;
  return active;
}

double SparseCentralDifference::energy(const SparseSystem& system, const State& at_t) {
  if (!within_limit_) return system.energy(at_t.u, at_t.v);
  scratch_ = (u_ - u_previous_) / dt_;
  u_next_ = 0.5 * (u_ + u_previous_);
  return central_difference_energy(quadratic_form(system.mass, scratch_),
                                   quadratic_form(system.stiffness, scratch_),
                                   quadratic_form(system.stiffness, u_next_), dt_);
}

Eigen::VectorXd consistent_acceleration(const SparseSystem& system, const State& state) {
  const Eigen::Index n = system.size();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
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

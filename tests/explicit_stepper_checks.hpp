// What the tests of the explicit steppers with a state of their own (core/methods/noh_bathe.hpp,
// core/methods/kim_explicit.hpp, core/methods/kr_alpha.hpp) measure the same way: the one-step
// matrix of a unit oscillator, column by column, for the amplification-matrix checks; and the
// errors of the first elastic mode under step halving, for the convergence orders. Each stepper has
// initialize(system, coefficients, dt, state) and step(system, state).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <vector>

#include "core/common/state.hpp"
#include "core/model/second_order_system.hpp"
#include "test_support.hpp"

namespace impactid::testing {

/// The stepper's one-step map on x = (u, Δt·v, Δt²·a) of ü + u = 0 with Δt = Ω: column j is
/// one step from the j-th unit vector.
template <class Stepper, class Coefficients>
Eigen::Matrix3d stepped_matrix(const Coefficients& coefficients, double omega_dt) {
  const SecondOrderSystem oscillator = unit_oscillator();
  const double dt = omega_dt;
  Eigen::Matrix3d a;
  for (int j = 0; j < 3; ++j) {
    State s;
    s.u = Eigen::VectorXd::Constant(1, j == 0 ? 1.0 : 0.0);
    s.v = Eigen::VectorXd::Constant(1, j == 1 ? 1.0 / dt : 0.0);
    s.a = Eigen::VectorXd::Constant(1, j == 2 ? 1.0 / (dt * dt) : 0.0);
    Stepper stepper;
    EXPECT_TRUE(stepper.initialize(oscillator, coefficients, dt, s));
    stepper.step(oscillator, s);
    a.col(j) = Eigen::Vector3d(s.u[0], dt * s.v[0], dt * dt * s.a[0]);
  }
  return a;
}

/// Relative energy-norm errors at T = 1 of the first elastic mode of damped_free_rod(a1)
/// started displaced, Δt = T/40 … T/640 (Ω_max of the lumped 10-element rod is 20·Δt <= 0.5).
template <class Stepper, class Coefficients>
std::vector<double> first_mode_errors(double a1, const Coefficients& coefficients) {
  const SecondOrderSystem system = damped_free_rod(a1);
  const Mode mode = dense_mode(system, 1);
  const ModalExact exact{mode.omega, 0.5 * a1 * mode.omega};
  std::vector<double> errors;
  for (long steps = 40; steps <= 640; steps *= 2) {
    State s = make_state(mode.phi, Eigen::VectorXd::Zero(mode.phi.size()));
    s.a = consistent_acceleration(system, s);
    Stepper stepper;
    EXPECT_TRUE(stepper.initialize(system, coefficients, 1.0 / steps, s));
    for (long i = 0; i < steps; ++i) stepper.step(system, s);
    EXPECT_NEAR(s.t, 1.0, 1e-12);
    errors.push_back(energy_norm_error(system, mode.omega, s.u - mode.phi * exact.q(1.0),
                                       s.v - mode.phi * exact.dq(1.0)) /
                     mode.omega);
  }
  return errors;
}

}  // namespace impactid::testing

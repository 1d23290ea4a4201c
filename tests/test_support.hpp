// Helpers shared by the tests: independent references (dense eigenpairs of a free rod), a
// driver for ImplicitIntegrator, and observed convergence orders from step halving.
// Nothing here calls into the code under test to produce an expected value.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/common/state.hpp"
#include "core/methods/implicit_integrator.hpp"
#include "core/model/rod_scene.hpp"
#include "core/model/second_order_system.hpp"
#include "core/run/simulation.hpp"

namespace impactid::testing {

/// A free-free rod without a wall: L = E = ρ = A = 1, so c = 1 and h = 1/n.
inline SecondOrderSystem free_rod(int elements, MassMatrix mass = MassMatrix::lumped) {
  RodScene scene;
  scene.length = 1.0;
  scene.youngs_modulus = 1.0;
  scene.density = 1.0;
  scene.area = 1.0;
  scene.elements = elements;
  scene.mass = mass;
  SecondOrderSystem system = assemble_rod(scene);
  system.gap = std::numeric_limits<double>::infinity();
  return system;
}

struct Mode {
  double omega;         ///< angular frequency [rad/s]
  Eigen::VectorXd phi;  ///< M-normalised: φᵀMφ = 1, contact-end entry positive
};

/// The k-th eigenpair of K φ = ω² M φ from Eigen's dense generalized solver (k = 0 is the rigid
/// mode of a free rod; test_support.cpp).
Mode dense_mode(const SecondOrderSystem& system, int k);

/// State with displacement u, velocity v, zero contact force, at t = 0 (acceleration unset).
inline State make_state(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  State s;
  s.u = u;
  s.v = v;
  s.a = Eigen::VectorXd::Zero(u.size());
  return s;
}

/// Energy norm of the error, sqrt(ω²·eᵤᵀMeᵤ + eᵥᵀMeᵥ): sensitive to phase and amplitude errors
/// alike, whatever the final time.
inline double energy_norm_error(const SecondOrderSystem& system, double omega,
                                const Eigen::VectorXd& du, const Eigen::VectorXd& dv) {
  return std::sqrt(omega * omega * system.mass.quadratic_form(du) +
                   system.mass.quadratic_form(dv));
}

/// Runs `steps` implicit steps of size dt from `initial` (acceleration made consistent here).
inline State run_implicit(const SecondOrderSystem& system, const ImplicitCoefficients& c,
                          double dt, long steps, State initial) {
  ImplicitIntegrator integrator;
  if (!integrator.initialize(system, c, dt)) {
    initial.u.setConstant(std::numeric_limits<double>::quiet_NaN());
    return initial;
  }
  initial.a = consistent_acceleration(system, initial);
  for (long i = 0; i < steps; ++i) integrator.step(system, initial);
  return initial;
}

/// ü + u = 0 as a one-degree-of-freedom SecondOrderSystem (m = k = 1, no damping): its one-step
/// matrices at Ω = Δt are the methods' amplification matrices.
inline SecondOrderSystem unit_oscillator() {
  SecondOrderSystem oscillator;
  oscillator.mass = Tridiagonal::zero(1);
  oscillator.mass.diag[0] = 1.0;
  oscillator.stiffness = Tridiagonal::zero(1);
  oscillator.stiffness.diag[0] = 1.0;
  oscillator.damping = Tridiagonal::zero(1);
  return oscillator;
}

/// The one-step amplification matrix of `c` on the undamped oscillator ü + u = 0 at Ω = ω·Δt =
/// dt, measured by stepping ImplicitIntegrator from the three unit states (u, Δt·v, Δt²·a) of a
/// one-degree-of-freedom SecondOrderSystem, column by column; NaN when it does not initialize
/// (test_support.cpp).
Eigen::Matrix3d stepped_amplification(const ImplicitCoefficients& c, double dt);

/// The spectral radius of stepped_amplification(c, dt); NaN when the integrator does not
/// initialize.
double spectral_radius(const ImplicitCoefficients& c, double dt);

/// The eigenvalues of a small dense matrix (an amplification or companion matrix), and the
/// largest of their moduli (test_support.cpp).
Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& a);
double spectral_radius_of(const Eigen::MatrixXd& a);

/// log2(e_k / e_{k+1}) for errors at successively halved steps.
inline std::vector<double> observed_orders(const std::vector<double>& errors) {
  std::vector<double> orders;
  for (std::size_t k = 0; k + 1 < errors.size(); ++k) {
    orders.push_back(std::log2(errors[k] / errors[k + 1]));
  }
  return orders;
}

/// Options for tests of the integrators: full histories, every step computed (free flight
/// included) and the energy bound checked at every step.
inline RunOptions stepping_options(double energy_growth_limit = RunOptions{}.energy_growth_limit) {
  RunOptions options;
  options.energy_growth_limit = energy_growth_limit;
  options.record_history = true;
  options.skip_free_flight = false;
  options.energy_check_interval = 1;
  return options;
}

/// One simulate() run with its trace copied out of the workspace.
struct Run {
  RunSummary summary;
  ContactTrace trace;
};
inline Run run(const RodScene& scene, const MethodParams& method,
               RunOptions options = stepping_options()) {
  SimulationWorkspace workspace;
  Run r;
  r.summary = simulate(scene, method, options, workspace);
  r.trace = workspace.trace;
  return r;
}

/// Largest |a_i − b_i|; NaN if any difference is NaN, +inf if the sizes differ.
inline double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = std::abs(a[i] - b[i]);
    if (std::isnan(d)) return d;
    worst = std::max(worst, d);
  }
  return worst;
}

// A free rod of 10 elements with stiffness-proportional damping C = a1·K, so that each mode is
// q'' + 2ζω·q' + ω²·q = 0 with ζ = a1·ω/2.
inline SecondOrderSystem damped_free_rod(double a1) {
  SecondOrderSystem system = free_rod(10);
  system.damping = system.stiffness.combined(a1, system.stiffness, 0.0);
  return system;
}

// The exact modal solution from q(0) = 1, q'(0) = 0: q = e^(−ζωt)(cos ω_d t + ζω/ω_d sin ω_d t),
// q' = −(ω²/ω_d)·e^(−ζωt)·sin ω_d t.
struct ModalExact {
  double omega, zeta;
  double q(double t) const {
    const double wd = omega * std::sqrt(1.0 - zeta * zeta);
    return std::exp(-zeta * omega * t) * (std::cos(wd * t) + zeta * omega / wd * std::sin(wd * t));
  }
  double dq(double t) const {
    const double wd = omega * std::sqrt(1.0 - zeta * zeta);
    return -omega * omega / wd * std::exp(-zeta * omega * t) * std::sin(wd * t);
  }
};

}  // namespace impactid::testing

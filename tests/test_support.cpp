// The helpers of test_support.hpp that use Eigen's eigensolvers, compiled once here:
// instantiated in every test that includes the header, they took most of each test's compile
// time.
#include "test_support.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

namespace impactid::testing {

Mode dense_mode(const SecondOrderSystem& system, int k) {
  const Eigen::MatrixXd m = system.mass.dense();
  const Eigen::MatrixXd kk = system.stiffness.dense();
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(kk, m);
  Mode mode{std::sqrt(std::max(0.0, solver.eigenvalues()[k])), solver.eigenvectors().col(k)};
  mode.phi /= std::sqrt(mode.phi.dot(m * mode.phi));
  if (mode.phi[mode.phi.size() - 1] < 0) mode.phi = -mode.phi;
  return mode;
}

Eigen::Matrix3d stepped_amplification(const ImplicitCoefficients& c, double dt) {
  const SecondOrderSystem oscillator = unit_oscillator();
  ImplicitIntegrator integrator;
  Eigen::Matrix3d amplification;
  if (!integrator.initialize(oscillator, c, dt)) {
    amplification.setConstant(std::numeric_limits<double>::quiet_NaN());
    return amplification;
  }
  for (int j = 0; j < 3; ++j) {
    State s;
    s.u = Eigen::VectorXd::Constant(1, j == 0 ? 1.0 : 0.0);
    s.v = Eigen::VectorXd::Constant(1, j == 1 ? 1.0 / dt : 0.0);
    s.a = Eigen::VectorXd::Constant(1, j == 2 ? 1.0 / (dt * dt) : 0.0);
    integrator.step(oscillator, s);
    amplification.col(j) = Eigen::Vector3d(s.u[0], dt * s.v[0], dt * dt * s.a[0]);
  }
  return amplification;
}

double spectral_radius(const ImplicitCoefficients& c, double dt) {
  const Eigen::Matrix3d amplification = stepped_amplification(c, dt);
  if (std::isnan(amplification(0, 0))) return std::numeric_limits<double>::quiet_NaN();
  return spectral_radius_of(amplification);
}

Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& a) { return a.eigenvalues(); }

double spectral_radius_of(const Eigen::MatrixXd& a) {
  return eigenvalues(a).cwiseAbs().maxCoeff();
}

}  // namespace impactid::testing

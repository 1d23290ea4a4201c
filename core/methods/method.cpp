#include "core/methods/method.hpp"

#include <cmath>

namespace impactid {

const char* to_string(CdmVelocity kind) {
  return kind == CdmVelocity::central ? "central" : "backward";
}
std::optional<CdmVelocity> cdm_velocity_from_string(const std::string& name) {
  if (name == "central") return CdmVelocity::central;
  if (name == "backward") return CdmVelocity::backward;
  return std::nullopt;
}

const char* to_string(ContactWeighting kind) {
  return kind == ContactWeighting::endpoint ? "endpoint" : "weighted";
}
std::optional<ContactWeighting> contact_weighting_from_string(const std::string& name) {
  if (name == "endpoint") return ContactWeighting::endpoint;
  if (name == "weighted") return ContactWeighting::weighted;
  return std::nullopt;
}

MethodKind kind_of(const MethodParams& params) {
  // MethodParams lists its alternatives in MethodKind's order (method.hpp says so, and
  // tests/method_registry_test.cpp checks every kind through default_params()).
  if (const auto* registered = std::get_if<RegisteredMethodParams>(&params)) {
    return registered->kind;
  }
  return static_cast<MethodKind>(params.index());
}

BetaGamma newmark_from_delta(double delta) {
  return {0.25 * (1.0 + delta) * (1.0 + delta), 0.5 + delta};
}

double rho_bathe_default_gamma(double rho_inf) {
  if (rho_inf >= 1.0) return 0.5;
  return (2.0 - std::sqrt(2.0 + 2.0 * rho_inf)) / (1.0 - rho_inf);
}

CompositeCoefficients composite_step_coefficients(double rho_inf, double gamma) {
  CompositeCoefficients c{};
  c.gamma = gamma;
  c.q1 = (rho_inf + 1.0) / (2.0 * gamma * (rho_inf - 1.0) + 4.0);
  c.q2 = 0.5 - gamma * c.q1;
  c.q0 = 1.0 - c.q1 - c.q2;
  c.first = {0.25, 0.25, 0.5, 0.5, 0.0, 0.0, 1.0};  // trapezoidal: β = 1/4, γ = 1/2
  c.second = {0.0, c.q2 * c.q2, 0.0, c.q2, 0.0, 0.0, 1.0};
  return c;
}

}  // namespace impactid

#include "core/reference/clamped_bar_exact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace impactid {

namespace {

constexpr double kPeriod = 3.0;  // in τ = ct/L

// s mod 3, in [0, 3).
double phase_of(double s) {
  const double r = s - kPeriod * std::floor(s / kPeriod);
  return r >= kPeriod ? r - kPeriod : r;  // round-off can leave exactly 3
}

// P(s) = k/2 + (|s − 3k − 1| − 1)/2 with k = ⌊s/3⌋: continuous, slope −½ then +½.
double profile(double s) {
  const double k = std::floor(s / kPeriod);
  return 0.5 * k + 0.5 * (std::abs(s - kPeriod * k - 1.0) - 1.0);
}

// P'(s): −½ for s mod 3 in (0, 1), +½ in (1, 3); within `tolerance` of a jump (s mod 3 = 0 or 1)
// the mean of the two sides, 0.
double slope(double s, double tolerance) {
  const double r = phase_of(s);
  if (std::abs(r - 1.0) <= tolerance || r <= tolerance || r >= kPeriod - tolerance) return 0.0;
  return r < 1.0 ? -0.5 : 0.5;
}

}  // namespace

std::optional<ParameterError> validate(const ClampedBarParams& p) {
  for (auto error : {
           require_positive_finite("length", p.length),
           require_positive_finite("youngs_modulus", p.youngs_modulus),
           require_positive_finite("density", p.density),
           require_positive_finite("amplitude", p.amplitude),
       }) {
    if (error) return error;
  }
  // The scales of the solution must be numbers too (E/ρ or a·E can overflow, or underflow to 0).
  const double c = std::sqrt(p.youngs_modulus / p.density);
  for (const double scale :
       {c, p.length / c, p.amplitude * c / p.length, p.amplitude * p.youngs_modulus / p.length,
        p.amplitude * p.amplitude * p.youngs_modulus / p.length}) {
    if (!(std::isfinite(scale) && scale > 0.0)) {
      return ParameterError{"youngs_modulus", format_value(p.youngs_modulus),
                            "with density, length and amplitude must give positive, finite c, "
                            "L/c, a·c/L, a·E/L and a²E/L"};
    }
  }
  return std::nullopt;
}

ClampedBarExact::ClampedBarExact(const ClampedBarParams& params) : params_(params) {
  if (const auto error = validate(params)) {
    throw std::invalid_argument("ClampedBarExact: " + error->field + " = " + error->value + ": " +
                                error->constraint);
  }
  speed_ = std::sqrt(params.youngs_modulus / params.density);
  transit_ = params.length / speed_;
  velocity_ = params.amplitude * speed_ / params.length;
  pressure_ = params.amplitude * params.youngs_modulus / params.length;
  energy_constant_ = 0.5 * params.amplitude * pressure_;
}

double ClampedBarExact::displacement(double x, double t) const {
  return point(x, t, 0.0).displacement;
}

BarPointValues ClampedBarExact::point(double x, double t, double jump_tolerance) const {
  if (!(x >= 0.0 && x <= params_.length)) {
    throw std::out_of_range("ClampedBarExact: x = " + format_value(x) + " lies outside [0, " +
                            format_value(params_.length) + "]");
  }
  // Reduced to one period first, so that P's arguments stay in [−2, 3] at any t.
  const double tau = phase_of(t / transit_);
  const double xi = x / params_.length;
  const double tolerance = jump_tolerance / transit_;
  const double outgoing = slope(tau - xi, tolerance);  // P'(τ − ξ): w+ from the contact end
  const double reflected = slope(tau + xi - 2.0, tolerance);  // P'(τ + ξ − 2): w− from the clamp
  return {params_.amplitude * (profile(tau - xi) - profile(tau + xi - 2.0)),
          velocity_ * (outgoing - reflected), -pressure_ * (outgoing + reflected)};
}

ContactNodeValues ClampedBarExact::at(double t, double jump_tolerance) const {
  const BarPointValues end = point(0.0, t, jump_tolerance);
  return {-end.stress, end.velocity, end.displacement};
}

bool ClampedBarExact::in_contact(double t) const {
  const double tau = phase_of(t / transit_);
  return tau >= 1.0 && tau <= 2.0;
}

std::vector<ContactEpisode> ClampedBarExact::episodes(double t_end) const {
  constexpr double kMostPeriods = 1e7;
  if (!(std::isfinite(t_end) && t_end >= 0.0 && t_end <= kMostPeriods * period())) {
    throw std::invalid_argument("ClampedBarExact::episodes: t_end = " + format_value(t_end) +
                                ": must be >= 0 and span at most 1e7 periods (" +
                                format_value(kMostPeriods * period()) + ")");
  }
  std::vector<ContactEpisode> result;
  for (long k = 0;; ++k) {
    const double start = (3.0 * k + 1.0) * transit_;
    if (start > t_end) break;
    const double end = std::min((3.0 * k + 2.0) * transit_, t_end);
    result.push_back({start, end, pressure_ * (end - start)});
  }
  return result;
}

double ClampedBarExact::energy(double t) const {
  // v and σ are constant between the (at most two) points where τ ∓ ξ crosses an integer.
  const double tau = phase_of(t / transit_);
  std::array<double, 4> cuts{0.0, tau - std::floor(tau), std::ceil(tau) - tau, 1.0};
  std::sort(cuts.begin(), cuts.end());
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double width = cuts[i + 1] - cuts[i];
    if (width <= 0.0) continue;
    const BarPointValues mid = point(0.5 * (cuts[i] + cuts[i + 1]) * params_.length, t, 0.0);
    sum += width * (0.5 * params_.density * mid.velocity * mid.velocity +
                    0.5 * mid.stress * mid.stress / params_.youngs_modulus);
  }
  return sum * params_.length;
}

}  // namespace impactid

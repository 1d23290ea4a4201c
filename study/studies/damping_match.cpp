#include "study/studies/damping_match.hpp"

#include <array>
#include <cmath>
#include <limits>

#include "core/spectral/amplification.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

constexpr std::array<DampingFamilyInfo, 9> kFamilies{{
    {DampingFamily::newmark, "newmark", "newmark", "delta", 0.0, 2.0},
    {DampingFamily::hht_eq19, "hht-eq19", "hht (delta = -1.5*alpha)", "alpha", 0.0, -0.5},
    {DampingFamily::hht_eq15, "hht-eq15", "hht (delta = -alpha)", "alpha", 0.0, -0.5},
    {DampingFamily::generalized_alpha, "generalized-alpha", "generalized-alpha", "rho_inf", 1.0,
     0.0},
    {DampingFamily::rho_bathe, "rho-bathe", "rho-bathe", "rho_inf", 1.0, 0.0},
    // Wilson-θ's ξ̄ grows with θ from its stability bound (1 + √3)/2 (ξ̄(1) = 0.034 there);
    // 4 reaches ξ̄(1) = 0.2 and more, beyond any damping a user would match.
    {DampingFamily::wilson_theta, "wilson-theta", "wilson-theta", "theta", 1.3660254037844386, 4.0},
    // p = ½ has no dissipation; p < 1 by its range (0.99: the scan's end inside it).
    {DampingFamily::noh_bathe, "noh-bathe", "noh-bathe", "p", 0.5, 0.99},
    // Kim's p = ⅓ is the least dissipative end of its range, ½ the most.
    {DampingFamily::kim_explicit, "kim-explicit", "kim-explicit", "p", 1.0 / 3.0, 0.5},
    {DampingFamily::kr_alpha, "kr-alpha", "kr-alpha", "rho_inf", 1.0, 0.0},
}};

double damping_ratio(DampingFamily family, double parameter, double omega_dt) {
  return spectral_properties(family_params(family, parameter), omega_dt).damping_ratio;
}

}  // namespace

std::span<const DampingFamilyInfo> damping_families() {
  return kFamilies;
}

const DampingFamilyInfo& family_info(DampingFamily family) {
  return kFamilies[static_cast<std::size_t>(family)];
}

MethodParams family_params(DampingFamily family, double parameter) {
  switch (family) {
    case DampingFamily::newmark:
      return NewmarkParams{.delta = parameter};
    case DampingFamily::hht_eq19:
      return HhtParams{.alpha = parameter, .delta = -1.5 * parameter};
    case DampingFamily::hht_eq15:
      return HhtParams{.alpha = parameter};
    case DampingFamily::generalized_alpha:
      return GeneralizedAlphaParams{.rho_inf = parameter};
    case DampingFamily::rho_bathe:
      return RhoBatheParams{.rho_inf = parameter};
    case DampingFamily::wilson_theta:
      return WilsonThetaParams{.theta = parameter};
    case DampingFamily::noh_bathe:
      return NohBatheParams{.p = parameter};
    case DampingFamily::kim_explicit:
      return KimExplicitParams{.p = parameter};
    case DampingFamily::kr_alpha:
      return KrAlphaParams{.rho_inf = parameter};
  }
  return BackwardEulerParams{};
}

DampingMatch match_damping(DampingFamily family, double omega_dt, double target_damping_ratio) {
  DampingMatch match;
  match.family = family;
  match.parameter = match.damping_ratio = kNaN;
  match.attainable_min = match.attainable_max = kNaN;
  if (!(std::isfinite(omega_dt) && omega_dt > 0.0 && std::isfinite(target_damping_ratio))) {
    return match;
  }
  const DampingFamilyInfo& f = family_info(family);
  const auto parameter_at = [&](int i) {
    if (i == kDampingScanIntervals) return f.damped_end;  // exactly the bound
    return f.undamped_end + (f.damped_end - f.undamped_end) * i / kDampingScanIntervals;
  };
  const auto excess = [&](double p) {
    return damping_ratio(family, p, omega_dt) - target_damping_ratio;
  };

  double bracket_lo = kNaN, bracket_hi = kNaN, exact = kNaN;
  double previous_p = kNaN, previous_f = kNaN;
  for (int i = 0; i <= kDampingScanIntervals; ++i) {
    const double p = parameter_at(i);
    const double xi = damping_ratio(family, p, omega_dt) + 0.0;  // + 0.0: no -0 at the undamped end
    const double fp = xi - target_damping_ratio;
    if (!std::isnan(xi)) {
      match.attainable_min =
          std::isnan(match.attainable_min) ? xi : std::min(match.attainable_min, xi);
      match.attainable_max =
          std::isnan(match.attainable_max) ? xi : std::max(match.attainable_max, xi);
    }
    // A root at a sample, or a sign change between two oscillatory neighbours.
    const bool at_sample = fp == 0.0;
    const bool crossed = !std::isnan(fp) && !std::isnan(previous_f) && previous_f != 0.0 &&
                         (fp < 0.0) != (previous_f < 0.0) && !at_sample;
    if (at_sample || crossed) {
      ++match.roots;
      if (match.roots == 1) {
        if (at_sample) {
          exact = p;
        } else {
          bracket_lo = previous_p;
          bracket_hi = p;
        }
      }
    }
    previous_p = p;
    previous_f = fp;
  }
  if (match.roots == 0) return match;

  if (std::isnan(exact)) {
    // Bisection down to adjacent doubles: the sign at bracket_lo is kept throughout.
    const bool low_negative = excess(bracket_lo) < 0.0;
    for (int iteration = 0; iteration < 200; ++iteration) {
      const double mid = 0.5 * (bracket_lo + bracket_hi);
      if (mid == bracket_lo || mid == bracket_hi) break;
      const double fm = excess(mid);
      if (fm == 0.0) {
        bracket_lo = bracket_hi = mid;
        break;
      }
      if (std::isnan(fm)) break;  // cannot happen between oscillatory samples; keep the bracket
      if ((fm < 0.0) == low_negative) {
        bracket_lo = mid;
      } else {
        bracket_hi = mid;
      }
    }
    const double f_lo = std::abs(excess(bracket_lo)), f_hi = std::abs(excess(bracket_hi));
    exact = f_lo <= f_hi ? bracket_lo : bracket_hi;
  }
  match.reachable = true;
  match.parameter = exact;
  match.damping_ratio = damping_ratio(family, exact, omega_dt);
  return match;
}

std::vector<std::pair<const char*, double>> family_parameters(DampingFamily family, double p) {
  switch (family) {
    case DampingFamily::newmark:
      return {{"delta", p}};
    case DampingFamily::hht_eq19:
      return {{"alpha", p}, {"delta", -1.5 * p}};
    case DampingFamily::hht_eq15:
      return {{"alpha", p}, {"delta", -p}};
    case DampingFamily::generalized_alpha:
    case DampingFamily::rho_bathe:
    case DampingFamily::kr_alpha:
      return {{"rho_inf", p}};
    case DampingFamily::wilson_theta:
      return {{"theta", p}};
    case DampingFamily::noh_bathe:
    case DampingFamily::kim_explicit:
      return {{"p", p}};
  }
  return {};
}

const char* family_method(DampingFamily family) {
  switch (family) {
    case DampingFamily::newmark:
      return "newmark";
    case DampingFamily::hht_eq19:
    case DampingFamily::hht_eq15:
      return "hht";
    case DampingFamily::generalized_alpha:
      return "generalized-alpha";
    case DampingFamily::rho_bathe:
      return "rho-bathe";
    case DampingFamily::wilson_theta:
      return "wilson-theta";
    case DampingFamily::noh_bathe:
      return "noh-bathe";
    case DampingFamily::kim_explicit:
      return "kim-explicit";
    case DampingFamily::kr_alpha:
      return "kr-alpha";
  }
  return "";
}

std::span<const std::pair<const char*, MethodParams>> fixed_damping_methods() {
  static const std::pair<const char*, MethodParams> fixed[] = {
      {"backward-euler", BackwardEulerParams{}},
      {"cdm", CentralDifferenceParams{}},
      {"bathe", BatheParams{}},
      {"tr-bdf2", TrBdf2Params{}},
      {"houbolt", HouboltParams{}},
  };
  return fixed;
}

}  // namespace impactid

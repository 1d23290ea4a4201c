#include "study/studies/damping_match.hpp"

#include <cmath>
#include <limits>

#include "core/methods/method_registry.hpp"
#include "core/spectral/amplification.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A family with the method it belongs to.
struct Family {
  DampingFamilyInfo info;
  const MethodDescriptor* method;
  const MethodDampingFamily* family;
};

// Every registered method's families, in registry order; built on first use.
struct Families {
  std::vector<Family> all;
  std::vector<DampingFamilyInfo> infos;
  std::vector<std::pair<const char*, MethodParams>> fixed;

  Families() {
    for (const MethodDescriptor& m : method_registry()) {
      if (m.damping_families.empty()) fixed.emplace_back(m.name, default_params(m.kind));
      for (const MethodDampingFamily& f : m.damping_families) {
        const DampingFamilyInfo info{
            DampingFamily{all.size()}, f.name, f.label, f.parameter, f.undamped_end, f.damped_end};
        all.push_back({info, &m, &f});
        infos.push_back(info);
      }
    }
  }
};

const Families& families() {
  static const Families registered;
  return registered;
}

const Family& family_of(DampingFamily family) {
  return families().all[static_cast<std::size_t>(family)];
}

double damping_ratio(DampingFamily family, double parameter, double omega_dt) {
  return spectral_properties(family_params(family, parameter), omega_dt).damping_ratio;
}

}  // namespace

std::span<const DampingFamilyInfo> damping_families() {
  return families().infos;
}

const DampingFamilyInfo& family_info(DampingFamily family) {
  return family_of(family).info;
}

std::optional<DampingFamily> find_damping_family(std::string_view name) {
  for (const DampingFamilyInfo& f : damping_families()) {
    if (name == f.name) return f.family;
  }
  return std::nullopt;
}

MethodParams family_params(DampingFamily family, double parameter) {
  return family_of(family).family->params(parameter);
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
  const MethodDampingFamily& f = *family_of(family).family;
  if (f.parameters == nullptr) return {{f.parameter, p}};
  return f.parameters(p);
}

const char* family_method(DampingFamily family) {
  return family_of(family).method->name;
}

std::span<const std::pair<const char*, MethodParams>> fixed_damping_methods() {
  return families().fixed;
}

}  // namespace impactid

#include "metrics/verdict.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <utility>

namespace impactid {
namespace {

constexpr std::array<std::pair<Verdict, const char*>, 6> kNames{{
    {Verdict::accurate, "accurate"},
    {Verdict::oscillating, "oscillating"},
    {Verdict::inaccurate, "inaccurate"},
    {Verdict::unverified, "unverified"},
    {Verdict::unstable, "unstable"},
    {Verdict::failed, "failed"},
}};
constexpr std::array<Verdict, 6> kAll{Verdict::accurate,   Verdict::oscillating,
                                      Verdict::inaccurate, Verdict::unverified,
                                      Verdict::unstable,   Verdict::failed};

// One thresholded indicator: its name, the run's value and the largest accepted value.
struct Check {
  const char* name;
  double value;
  double limit;
};
std::array<Check, 2> errors(const Indicators& i, const VerdictThresholds& t) {
  return {{{"eps_p", i.eps_p, t.eps_p}, {"eps_v", i.eps_v, t.eps_v}}};
}
std::array<Check, 2> peaks(const Indicators& i, const VerdictThresholds& t) {
  return {{{"nop_p", i.nop_p, t.nop_p}, {"nop_v", i.nop_v, t.nop_v}}};
}

// Four significant digits for the run's value (a report, not a record), the threshold as given.
std::string check_text(const Check& c, const char* relation) {
  char value[32];
  std::snprintf(value, sizeof value, "%.4g", c.value);
  return std::string(c.name) + " = " + value + " " + relation + " " + format_value(c.limit);
}

}  // namespace

const char* to_string(Verdict verdict) {
  for (const auto& [v, name] : kNames) {
    if (v == verdict) return name;
  }
  return "?";
}

std::optional<Verdict> verdict_from_string(std::string_view name) {
  for (const auto& [v, text] : kNames) {
    if (name == text) return v;
  }
  return std::nullopt;
}

std::span<const Verdict> all_verdicts() {
  return kAll;
}

std::optional<ParameterError> validate(const VerdictThresholds& t) {
  for (const auto& [field, value] :
       {std::pair{"verdict_eps_p", t.eps_p}, std::pair{"verdict_nop_p", t.nop_p},
        std::pair{"verdict_eps_v", t.eps_v}, std::pair{"verdict_nop_v", t.nop_v}}) {
    if (!(value >= 0.0 && std::isfinite(value))) {
      return ParameterError{field, format_value(value), "must be >= 0 and finite"};
    }
  }
  return std::nullopt;
}

std::string thresholds_text(const VerdictThresholds& t) {
  return "eps_p <= " + format_value(t.eps_p) + ", nop_p <= " + format_value(t.nop_p) +
         ", eps_v <= " + format_value(t.eps_v) + ", nop_v <= " + format_value(t.nop_v);
}

Verdict judge(RunStatus status, const Indicators& indicators, bool reference_trusted,
              const VerdictThresholds& thresholds) {
  if (status == RunStatus::failed) return Verdict::failed;
  if (status == RunStatus::unstable) return Verdict::unstable;
  if (!reference_trusted) return Verdict::unverified;
  for (const Check& c : errors(indicators, thresholds)) {
    if (std::isnan(c.value)) return Verdict::unverified;
  }
  for (const Check& c : peaks(indicators, thresholds)) {
    if (std::isnan(c.value)) return Verdict::unverified;
  }
  for (const Check& c : errors(indicators, thresholds)) {
    if (c.value > c.limit) return Verdict::inaccurate;
  }
  for (const Check& c : peaks(indicators, thresholds)) {
    if (c.value > c.limit) return Verdict::oscillating;
  }
  return Verdict::accurate;
}

bool ranks_before(Verdict a, double eps_p_a, Verdict b, double eps_p_b) {
  if (a != b) return a < b;
  if (std::isnan(eps_p_a) || std::isnan(eps_p_b))
    return !std::isnan(eps_p_a) && std::isnan(eps_p_b);
  return eps_p_a < eps_p_b;
}

std::string verdict_reason(RunStatus status, const Indicators& indicators, bool reference_trusted,
                           const VerdictThresholds& thresholds) {
  const Verdict verdict = judge(status, indicators, reference_trusted, thresholds);
  std::string out;
  const auto add = [&](const std::string& s) { out += (out.empty() ? "" : ", ") + s; };
  switch (verdict) {
    case Verdict::failed:
    case Verdict::unstable:
      return std::string("the run is ") + to_string(status);
    case Verdict::unverified:
      if (!reference_trusted) return "the reference is not trusted";
      for (const Check& c : errors(indicators, thresholds)) {
        if (std::isnan(c.value)) add(std::string(c.name) + " has no value");
      }
      for (const Check& c : peaks(indicators, thresholds)) {
        if (std::isnan(c.value)) add(std::string(c.name) + " has no value");
      }
      return out;
    case Verdict::inaccurate:
    case Verdict::oscillating:
      for (const Check& c : errors(indicators, thresholds)) {
        if (c.value > c.limit) add(check_text(c, ">"));
      }
      for (const Check& c : peaks(indicators, thresholds)) {
        if (c.value > c.limit) add(check_text(c, ">"));
      }
      return out;
    case Verdict::accurate:
      return "within " + thresholds_text(thresholds);
  }
  return out;
}

}  // namespace impactid

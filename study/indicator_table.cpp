#include "study/indicator_table.hpp"

#include <array>

namespace impactid {
namespace {

constexpr std::array<IndicatorInfo, 9> kIndicators{{
    {"eps_p", "1",
     "eq. 18: sum_i |p_exact - p| / sum_i |p_exact| over t_i = i*dt, i = 1..N; exact value on a "
     "jump (within 1e-6*dt) is the mean of the one-sided limits",
     [](const Evaluation& e) { return e.indicators.eps_p; }},
    {"eps_v", "1", "eq. 18 for the contact-node velocity, same sampling as eps_p",
     [](const Evaluation& e) { return e.indicators.eps_v; }},
    {"nop_p", "1",
     "number of peaks of the pressure: local maxima (flat top counted once, end samples never) "
     "with topographic prominence >= peak_prominence*rho*c*v0",
     [](const Evaluation& e) { return e.indicators.nop_p; }},
    {"nop_v", "1",
     "number of peaks of the contact-node velocity: same rule, prominence >= "
     "peak_prominence*|v0|",
     [](const Evaluation& e) { return e.indicators.nop_v; }},
    {"p_max", "MPa", "largest sampled contact pressure",
     [](const Evaluation& e) { return e.indicators.p_max; }},
    {"p_max_ratio", "1", "p_max / (rho*c*v0)",
     [](const Evaluation& e) { return e.indicators.p_max_ratio; }},
    {"contact_episodes", "1", "maximal runs of samples with a positive contact pressure",
     [](const Evaluation& e) { return e.indicators.contact_episodes; }},
    {"energy_ratio", "1", "kinetic + strain energy at the last sample / initial energy",
     [](const Evaluation& e) { return e.indicators.energy_ratio; }},
    {"wall_time_s", "s", "wall-clock time of the simulation (set-up and stepping)",
     [](const Evaluation& e) { return e.summary.wall_time_s; }},
}};

}  // namespace

std::span<const IndicatorInfo> indicator_table() { return kIndicators; }

const IndicatorInfo* find_indicator(std::string_view name) {
  for (const auto& info : kIndicators) {
    if (name == info.name) return &info;
  }
  return nullptr;
}

}  // namespace impactid

#include "metrics/indicator_table.hpp"

#include <array>

namespace impactid {
namespace {

constexpr std::array<IndicatorInfo, 12> kIndicators{{
    {"eps_p", "1",
     "eq. 18: sum_i |p_exact - p| / sum_i |p_exact| over t_i = i*dt, i = 1..N; exact value on a "
     "jump (within 1e-6*dt) is the mean of the one-sided limits",
     [](Evaluation& e) -> double& { return e.indicators.eps_p; }},
    {"eps_v", "1", "eq. 18 for the contact-node velocity, same sampling as eps_p",
     [](Evaluation& e) -> double& { return e.indicators.eps_v; }},
    {"nop_p", "1",
     "number of peaks of the pressure: local maxima (flat top counted once, end samples never) "
     "with topographic prominence >= peak_prominence*rho*c*v0",
     [](Evaluation& e) -> double& { return e.indicators.nop_p; }},
    {"nop_v", "1",
     "number of peaks of the contact-node velocity: same rule, prominence >= "
     "peak_prominence*|v0|",
     [](Evaluation& e) -> double& { return e.indicators.nop_v; }},
    {"p_max", "MPa", "largest sampled contact pressure",
     [](Evaluation& e) -> double& { return e.indicators.p_max; }},
    {"p_max_ratio", "1", "p_max / (rho*c*v0)",
     [](Evaluation& e) -> double& { return e.indicators.p_max_ratio; }},
    {"contact_episodes", "1", "maximal runs of samples with a positive contact pressure",
     [](Evaluation& e) -> double& { return e.indicators.contact_episodes; }},
    {"energy_ratio", "1", "kinetic + strain energy at the last sample / initial energy",
     [](Evaluation& e) -> double& { return e.indicators.energy_ratio; }},
    {"far_contact_episodes", "1",
     "with a far wall (far_gap): maximal runs of samples with a positive far-wall pressure; NaN "
     "without one",
     [](Evaluation& e) -> double& { return e.indicators.far_contact_episodes; }},
    {"impacts", "1",
     "with a far wall (far_gap): changes of the wall that alone holds the rod (samples with a "
     "positive pressure at one wall only): an episode at the wall touched last continues the "
     "same impact; samples where both walls push never start one, except as the run's first "
     "contact; NaN without one",
     [](Evaluation& e) -> double& { return e.indicators.impacts; }},
    {"max_penetration", "mm",
     "largest penetration of a wall by its contact node over the samples (<= 0: none), tracked "
     "with a far wall (far_gap), on a scene of bodies, and with contact = penalty or "
     "augmented-lagrangian; NaN otherwise",
     [](Evaluation& e) -> double& { return e.indicators.max_penetration; }},
    {"wall_time_s", "s",
     "wall-clock time of the simulation (set-up and stepping); points run together in the "
     "batched kernel share the batch's time divided by its runs",
     [](Evaluation& e) -> double& { return e.summary.wall_time_s; }},
}};

}  // namespace

std::span<const IndicatorInfo> indicator_table() {
  return kIndicators;
}

const IndicatorInfo* find_indicator(std::string_view name) {
  for (const auto& info : kIndicators) {
    if (name == info.name) return &info;
  }
  return nullptr;
}

}  // namespace impactid

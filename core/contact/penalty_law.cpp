// The penalty: λ = k·max(0, g), a spring of stiffness k that acts once a node penetrates
// (core/contact/contact_treatment.hpp: how each family of methods applies it, and why the
// default k is the contact dof's own stiffness). Its two parameters set k; the augmented
// Lagrangian takes them too.
#include "core/contact/penalty_law.hpp"

#include <cmath>
#include <limits>

#include "core/contact/contact_law_registry.hpp"

namespace impactid {

double penalty_stiffness(const ContactTreatment& t, double dof_stiffness) {
  return t.penalty_stiffness ? *t.penalty_stiffness : t.penalty_factor * dof_stiffness;
}
namespace {

constexpr ContactLawParameter kPenaltyParameters[] = {
    {"penalty_stiffness", false, "N/mm",
     "penalty stiffness k of every contact (penalty, augmented-lagrangian; default "
     "penalty_factor times each contact dof's stiffness), > 0",
     [](ContactTreatment& t, double v) { t.penalty_stiffness = v; },
     [](const ContactTreatment& t) {
       return t.penalty_stiffness.value_or(std::numeric_limits<double>::quiet_NaN());
     },
     [](const ContactTreatment& t) -> std::optional<ParameterError> {
       if (t.penalty_stiffness &&
           (!(*t.penalty_stiffness > 0.0) || !std::isfinite(*t.penalty_stiffness))) {
         return ParameterError{"penalty_stiffness", format_value(*t.penalty_stiffness),
                               "must be a finite number > 0 [N/mm]"};
       }
       return std::nullopt;
     }},
    {"penalty_factor", false, "",
     "k as a multiple of the contact dof's stiffness K_cc (E*A/h for the rod) when "
     "penalty_stiffness is not given (default 1), > 0; for augmented-lagrangian it sets only the "
     "iterations' speed, which falls with courant^2: raise it where steps end at the cap (10 for "
     "rho-bathe, tr-bdf2, noh-bathe, kim-explicit at courant 0.5; docs/methods.md)",
     [](ContactTreatment& t, double v) { t.penalty_factor = v; },
     [](const ContactTreatment& t) { return t.penalty_factor; },
     [](const ContactTreatment& t) -> std::optional<ParameterError> {
       if (!(t.penalty_factor > 0.0) || !std::isfinite(t.penalty_factor)) {
         return ParameterError{"penalty_factor", format_value(t.penalty_factor),
                               "must be a finite number > 0"};
       }
       return std::nullopt;
     }},
};

constexpr const char* kTakes[] = {"penalty_stiffness", "penalty_factor"};

}  // namespace

const ContactLawDescriptor& penalty_law() {
  static const ContactLawDescriptor law{
      .law = ContactLaw::penalty,
      .name = "penalty",
      .summary =
          "penalty springs lambda = k*max(0, g): contacts penetrate by lambda/k; the "
          "implicit methods and kr-alpha solve the spring with the step, the explicit ones "
          "apply it as a force, which shortens their stable step",
      .introduces = kPenaltyParameters,
      .parameters = kTakes,
      .springs = true,
      .explicit_force = true,
  };
  return law;
}

}  // namespace impactid

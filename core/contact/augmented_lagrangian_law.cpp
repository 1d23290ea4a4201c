// The augmented Lagrangian: Uzawa's iterations on the penalty problem of every method, from the
// penalty's solution to Lagrange's multiplier (core/contact/augmented_lagrangian_law.hpp). It takes
// the penalty's spring, which sets the iterations' speed, and introduces when to stop.
#include <string>

#include "core/contact/contact_law_registry.hpp"

namespace impactid {
namespace {

constexpr ContactLawParameter kAugmentedParameters[] = {
    {"augmented_tolerance", false, "",
     "augmented-lagrangian: iterate until the penetration is at most this fraction of the step's "
     "contact-free one (default 1e-6), in (0, 1)",
     [](ContactTreatment& t, double v) { t.augmented_tolerance = v; },
     [](const ContactTreatment& t) { return t.augmented_tolerance; },
     [](const ContactTreatment& t) -> std::optional<ParameterError> {
       if (!(t.augmented_tolerance > 0.0 && t.augmented_tolerance < 1.0)) {
         return ParameterError{"augmented_tolerance", format_value(t.augmented_tolerance),
                               "must lie in (0, 1)"};
       }
       return std::nullopt;
     }},
    {"augmented_max_iterations", true, "",
     "augmented-lagrangian: iterations per step at most (default 100), >= 1",
     [](ContactTreatment& t, double v) { t.augmented_max_iterations = static_cast<int>(v); },
     [](const ContactTreatment& t) { return static_cast<double>(t.augmented_max_iterations); },
     [](const ContactTreatment& t) -> std::optional<ParameterError> {
       if (t.augmented_max_iterations < 1) {
         return ParameterError{"augmented_max_iterations",
                               std::to_string(t.augmented_max_iterations),
                               "must be an integer >= 1"};
       }
       return std::nullopt;
     }},
};

constexpr const char* kTakes[] = {"penalty_stiffness", "penalty_factor", "augmented_tolerance",
                                  "augmented_max_iterations"};

}  // namespace

const ContactLawDescriptor& augmented_lagrangian_law() {
  static const ContactLawDescriptor law{
      .law = ContactLaw::augmented_lagrangian,
      .name = "augmented-lagrangian",
      .summary =
          "Uzawa's iterations on the penalty problem until the penetration is at most "
          "augmented_tolerance of the contact-free one: converges to Lagrange's "
          "multiplier, the iterations counted",
      .introduces = kAugmentedParameters,
      .parameters = kTakes,
      .springs = true,
      .iterates = true,
  };
  return law;
}

}  // namespace impactid

// Paoli–Schatzman's law (core/contact/paoli_schatzman_law.hpp): its descriptor, its one parameter
// (the coefficient of restitution), and the gap shifts of a constraint list.
#include "core/contact/paoli_schatzman_law.hpp"

#include <cmath>

#include "core/contact/constraint_list_law.hpp"
#include "core/contact/contact_law_registry.hpp"

namespace impactid {
namespace {

constexpr ContactLawParameter kPaoliSchatzmanParameters[] = {
    {"restitution", false, "",
     "paoli-schatzman: Newton's coefficient of restitution e of the impact law on "
     "(u_{n+1} + e*u_{n-1})/(1 + e) (default 0: Lagrange's law), in [0, 1]",
     [](ContactTreatment& t, double v) { t.restitution = v; },
     [](const ContactTreatment& t) { return t.restitution; },
     [](const ContactTreatment& t) -> std::optional<ParameterError> {
       if (!(t.restitution >= 0.0 && t.restitution <= 1.0)) {
         return ParameterError{"restitution", format_value(t.restitution), "must lie in [0, 1]"};
       }
       return std::nullopt;
     }},
};

constexpr const char* kTakes[] = {"restitution"};

}  // namespace

const ContactLawDescriptor& paoli_schatzman_law() {
  static const ContactLawDescriptor law{
      .law = ContactLaw::paoli_schatzman,
      .name = "paoli-schatzman",
      .summary =
          "Paoli-Schatzman's impact law: central difference's multiplier holds the gap on "
          "(u_{n+1} + e*u_{n-1})/(1 + e), e the coefficient of restitution; cdm only",
      .introduces = kPaoliSchatzmanParameters,
      .parameters = kTakes,
      .two_step_gap = true,
  };
  return law;
}

void restitution_gap_shifts(const std::vector<Constraint>& constraints,
                            const Eigen::VectorXd& u_previous, double restitution,
                            Eigen::VectorXd& shifts) {
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    shifts[static_cast<Eigen::Index>(k)] =
        restitution_gap_shift(restitution, constraint_violation(constraints[k], u_previous));
  }
}

}  // namespace impactid

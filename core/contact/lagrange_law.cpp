// Lagrange's law, the paper's and the default: g <= 0, λ >= 0, λ·g = 0, the gap held exactly by
// each method's multiplier (core/contact/contact_treatment.hpp). It has no parameters.
#include "core/contact/contact_law_registry.hpp"

namespace impactid {

const ContactLawDescriptor& lagrange_law() {
  static const ContactLawDescriptor law{
      .law = ContactLaw::lagrange,
      .name = "lagrange",
      .summary =
          "Lagrange multipliers (the paper's law, default): the gap holds exactly, "
          "lambda >= 0, lambda*g = 0",
  };
  return law;
}

}  // namespace impactid

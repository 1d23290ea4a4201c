// The penalty's own arithmetic: the stiffness k of each contact's spring, which resolve_contact()
// (core/contact/contact_treatment.hpp) gives every law with springs. Its descriptor, parameters
// and checks are in penalty_law.cpp.
//
// Thread safety: a pure function.
#pragma once

#include "core/contact/contact_law.hpp"

namespace impactid {

/// [N/mm] the spring k of a contact whose dof has stiffness K_cc: penalty_stiffness if given,
/// otherwise penalty_factor·K_cc.
double penalty_stiffness(const ContactTreatment& treatment, double dof_stiffness);

}  // namespace impactid

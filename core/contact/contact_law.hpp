// The contact law a run enforces its unilateral contacts by, and its settings as users give them:
// plain values, below the registry (core/contact/contact_law_registry.hpp: each law's name,
// parameters and validation) and the laws' arithmetic (core/contact/contact_treatment.hpp).
//
// Thread safety: values.
#pragma once

#include <optional>

namespace impactid {

/// The laws, each registered once (core/contact/contact_law_registry.hpp) and defined in its own
/// file (core/contact/<law>_law.cpp). Outside core/contact/ a law is named through the registry,
/// never by its value (tests/contact_law_ownership_test.py).
enum class ContactLaw { lagrange, penalty, augmented_lagrangian, paoli_schatzman };

/// A law with its parameters. Every field is validated whatever the law (validate(), in the
/// registry): a sweep crossing `contact` with `penalty_factor` must refuse a bad factor at its
/// Lagrange points too, not run them and fail at the penalty ones.
struct ContactTreatment {
  ContactLaw law = ContactLaw::lagrange;
  /// [N/mm] penalty stiffness k of every contact (penalty, augmented-lagrangian); > 0. Unset: k is
  /// penalty_factor times each contact dof's stiffness.
  std::optional<double> penalty_stiffness;
  double penalty_factor = 1.0;  ///< > 0; used when penalty_stiffness is unset
  /// augmented-lagrangian: stop once the largest penetration is at most this fraction of the
  /// step's largest contact-free penetration; in (0, 1).
  double augmented_tolerance = 1e-6;
  int augmented_max_iterations = 100;  ///< augmented-lagrangian: iterations per step at most; >= 1
  /// paoli-schatzman: Newton's coefficient of restitution e of the impact law on
  /// (u_{n+1} + e·u_{n−1})/(1 + e); in [0, 1]. At 0 the law is Lagrange's, bit for bit.
  double restitution = 0.0;

  bool operator==(const ContactTreatment&) const = default;
};

}  // namespace impactid

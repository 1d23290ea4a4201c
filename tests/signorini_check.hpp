// The Signorini conditions of a state, checked by the tests of the steppers with their own
// arithmetic: for every constraint of the system (the named wall and far wall, or the list; a
// sparse model's list) the violation g = G·u − gap, the multiplier λ, and whether λ > 0 comes
// with g = 0. Nothing here calls the code under test.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "core/second_order_system.hpp"
#include "core/sparse_system.hpp"
#include "core/state.hpp"

namespace impactid::testing {

/// Worst values over every constraint of every state recorded.
struct SignoriniRecord {
  double max_violation = -std::numeric_limits<double>::infinity();  ///< max g (> 0: penetration)
  double min_multiplier = std::numeric_limits<double>::infinity();  ///< min λ
  double max_gap_while_pushing = 0.0;  ///< max |g| where λ > 0 (complementarity)
  long pushing = 0;                    ///< (constraint, state) pairs with λ > 0
  long states = 0;

  void record(double g, double lambda) {
    max_violation = std::max(max_violation, g);
    min_multiplier = std::min(min_multiplier, lambda);
    if (lambda > 0.0) {
      max_gap_while_pushing = std::max(max_gap_while_pushing, std::abs(g));
      ++pushing;
    }
  }
};

inline double violation(const Constraint& c, const Eigen::VectorXd& u) {
  double g = -c.gap;
  if (c.plus >= 0) g += u[c.plus];
  if (c.minus >= 0) g -= u[c.minus];
  return g;
}

/// Adds every constraint of `system` at `state` to the record.
template <class System>
void record_signorini(const System& system, const State& state, SignoriniRecord& record) {
  ++record.states;
  for (std::size_t k = 0; k < system.constraints.size(); ++k) {
    record.record(violation(system.constraints[k], state.u),
                  state.multipliers[static_cast<Eigen::Index>(k)]);
  }
  if constexpr (std::is_same_v<System, SecondOrderSystem>) {
    if (system.has_contact()) {
      record.record(state.u[system.contact_dof] - system.gap, state.lambda);
    }
    if (system.has_far_contact()) {
      record.record(-state.u[system.far_contact_dof] - system.far_gap, state.far_lambda);
    }
  }
}

}  // namespace impactid::testing
